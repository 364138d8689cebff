// The device buffers of a render: the packed scene (read-only) and the wavefront state (queues, film).
#pragma once
#include <cstdint>

#include "render/memory_estimate.h"
#include "scene/pack.h"
#include "shared/layout.h"
#include "vk/buffer.h"

namespace fh {

namespace vk {
class BindingTable;
class Context;
}  // namespace vk

struct GpuBuffers {
    vk::Buffer params;
    vk::Buffer nodes;
    vk::Buffer tri_positions;
    vk::Buffer tri_shading;
    vk::Buffer materials;
    vk::Buffer emitters;
    vk::Buffer punctual_lights;
    vk::Buffer light_tree;         // LightTreeNode[] (EFFECT_LIGHT_TREE; else one node)
    vk::Buffer ggx_albedo;         // the BSDF's albedo tables, GGX and sheen (uniform)
    vk::Buffer counters;           // device-local: atomics stay on the device
    vk::Buffer counters_readback;  // host-visible copy made at the end of each submission
    vk::Buffer paths;
    vk::Buffer rays;
    vk::Buffer hits;
    vk::Buffer shadow_rays;
    vk::Buffer film;
    vk::Buffer tri_attributes;     // textures and vertex colours (one dummy element when the scene has none)
    vk::Buffer texture_slots;
    vk::Buffer texture_images;
    vk::Buffer texels;
    vk::Buffer env_radiance;       // environment light (EFFECT_ENVIRONMENT)
    vk::Buffer env_cdf;
    vk::Buffer instances;          // two-level BVH (one dummy element when the scene has none)
    vk::Buffer material_layers;    // KHR material extensions, one per material
    vk::Buffer path_light_points;  // per path: where its last NEE stood (EFFECT_LIGHT_TREE; else one element)
    vk::Buffer path_aovs;          // per path: its AOVs (--aov; else one element)
    vk::Buffer aov_film;           // per pixel: the AOVs' sums (--aov; else one element)
    vk::Buffer pixel_list;         // the order waves take the film's pixels in (--adaptive; else one word)
    vk::Buffer pixel_work;         // per pixel: its samples' work (--adaptive; else one word)
    vk::Buffer path_work;          // per path: its work so far (--adaptive; else one word)
    vk::Buffer path_media;         // the volumes each path is inside (EFFECT_VOLUME, _ABSORPTION; else one stack)
    vk::Buffer light_media;        // the volumes each light stands in (light subpaths with EFFECT_VOLUME; else one)
    vk::Buffer path_spectra;       // each path's wavelengths (EFFECT_SPECTRAL; else one element)
    vk::Buffer path_times;         // each path's time in the shutter (EFFECT_MOTION_BLUR; else one word)
    vk::Buffer glass_albedo;       // the glass lobe's albedo table (EFFECT_GLASS_MULTISCATTER; else one word)
    vk::Buffer anisotropic_albedo; // the anisotropic GGX lobe's (EFFECT_ANISOTROPY and _GGX_MULTISCATTER; else one word)
    vk::Buffer light_vertices;     // stored light-subpath vertices (`--integrator bdpt`; else one element)
    vk::Buffer path_mis;           // each path's MIS quantities (`--integrator bdpt`; else one element)
    vk::Buffer merge_points;       // `--integrator vcm` (else one element each): each light vertex's point and dvm,
    vk::Buffer path_dvm;           //   each path's dvm,
    vk::Buffer merge_grid;         //   the hash grid over the wave's light vertices
    vk::Buffer ray_sort;           // the ray sort's counts, offsets, keys and order (render/ray_sort.h)
};

// `effects`: the EFFECT_* set the stages are compiled with (buffers that only some effects read are sized
// for them: estimate_render_memory); `store`: what each path keeps besides its state (BDPT, the ray sort).
GpuBuffers create_gpu_buffers(const vk::Context& context, const PackedScene& scene, const gpu::FrameParams& frame,
                              EffectBits effects, const PathStore& store = {});
void bind_gpu_buffers(vk::BindingTable& table, const GpuBuffers& buffers);

}  // namespace fh
