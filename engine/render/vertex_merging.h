// Vertex connection and merging (`--integrator vcm`; shaders/lib/integrator/README.md "Vertex connection and
// merging"): the merging radius of each wave and the hash grid's size.
#pragma once
#include <cstdint>

#include "render/settings.h"
#include "scene/effect_bits.h"
#include "scene/pack.h"

namespace fh {

// The radius shrinks with the sample index n (from 1) as r_n = r_1 n^((alpha - 1) / 2) (Knaus and Zwicker 2011's
// progressive schedule, as SmallVCM has it): the merges' bias falls with r_n^2 while their variance grows more slowly
// than the samples' count falls it, so the image converges (consistent), and at any finite count it is biased.
inline constexpr double MERGE_RADIUS_ALPHA = 0.75;

// The radius for the wave that starts at `sample_index` (from 0): settings.merge_radius of the scene's
// bounding-sphere radius at the first sample.
float merge_radius_at(const RenderSettings& settings, double scene_radius, uint32_t sample_index);
// That bounding sphere's radius: half the diagonal of the scene's box (PackedScene::bounds_lo, bounds_hi).
double scene_bounding_radius(const PackedScene& scene);

// Whether a VCM wave must hold one sample index: a merge joins light vertices of every path in the wave, which must
// share the camera vertex's shutter time (motion blur) and wavelengths (dispersion). The shaders then draw both per
// sample index for every pixel (shaders/lib/sampling/path_sampler.glsl share_time_and_wavelengths).
bool waves_hold_one_sample(Integrator integrator, EffectBits effects);

// Buckets of the hash grid over a wave's light vertices: a power of two near a quarter of the slots (most light
// subpaths end long before their last slot), at least 1024.
uint32_t count_merge_grid_cells(uint32_t wave_capacity, uint32_t light_vertex_slots);

}  // namespace fh
