#include "render/vertex_merging.h"

#include <algorithm>
#include <cmath>

namespace fh {

float merge_radius_at(const RenderSettings& settings, double scene_radius, uint32_t sample_index) {
    const double n = double(sample_index) + 1.0;
    return float(double(settings.merge_radius) * scene_radius * std::pow(n, 0.5 * (MERGE_RADIUS_ALPHA - 1.0)));
}

double scene_bounding_radius(const PackedScene& scene) {
    return 0.5 * double(glm::length(scene.bounds_hi - scene.bounds_lo));
}

bool waves_hold_one_sample(Integrator integrator, EffectBits effects) {
    return integrator == Integrator::vcm && (effects & (gpu::EFFECT_SPECTRAL | gpu::EFFECT_MOTION_BLUR)) != 0;
}

uint32_t count_merge_grid_cells(uint32_t wave_capacity, uint32_t light_vertex_slots) {
    const uint64_t wanted = std::max<uint64_t>(uint64_t(wave_capacity) * light_vertex_slots / 4, 1024);
    uint64_t cells = 1024;
    while (cells < wanted && cells < (uint64_t(1) << 24)) cells *= 2;
    return uint32_t(cells);
}

}  // namespace fh
