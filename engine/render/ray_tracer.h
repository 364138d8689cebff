// The extend stage (closest hit) or the connect stage (any hit, shadow rays) alone over a given set of rays (no paths,
// no shading): the ray-tracing core measured apart from the path tracer (`fredholm bench --trace-rays [--any-hit]`) and
// checked against a brute force (tests/gpu).
#pragma once
#include <cstdint>
#include <vector>

#include "render/gpu_buffers.h"
#include "render/stage_table.h"
#include "scene/pack.h"
#include "shared/layout.h"

namespace fh {

namespace vk {
class Context;
}

struct TracedRays {
    std::vector<gpu::HitItem> hits;  // per ray, in order; triangle in BVH leaf order (INVALID_INDEX: a miss)
    uint32_t escaped_rays = 0;       // as the device counted them (count_on_device), else the misses in `hits`
    std::vector<double> seconds;     // GPU time of each repeat: extend's dispatch, and the ray sort's when it sorts
};

struct TracedShadowRays {
    std::vector<uint8_t> occluded;   // per ray, in order: 1 where something lies between origin and t_max
    std::vector<double> seconds;     // GPU time of connect's dispatch, per repeat
};

// Traces `rays` through the extend stage of `stages`, in `buffers` (its rays, hits and counters; at most as many rays as
// the hits buffer holds), `repeats` times, one submission each; sorted first (render/ray_sort.h) when the stages
// were built for it. Leaves the counters as the last dispatch left them. count_on_device: extend counts the escaped rays
// with an atomic per SIMD group (the stability tests check that counter); else they are counted from the hits on the host,
// and extend runs as in a render, where shade counts them (`bench --trace-rays` times it so).
TracedRays trace_ray_queue(const vk::Context& context, const StageTable& stages, GpuBuffers& buffers,
                           const std::vector<gpu::RayItem>& rays, uint32_t repeats, bool count_on_device = true);

class RayTracer {
public:
    // Buffers for up to `capacity` rays; the stages compiled for the scene's effects but `disabled_effects` (alpha
    // compiled out: every triangle opaque, as a tracer without an alpha test sees them); `sort_rays`: each trace sorts
    // the rays first (render/ray_sort.h), its time included.
    RayTracer(const vk::Context& context, const PackedScene& scene, uint32_t capacity, bool sort_rays = false,
              EffectBits disabled_effects = 0);

    // Traces `rays` (RayItem::path is ignored; origin_triangle in BVH leaf order) `repeats` times (count_on_device:
    // trace_ray_queue).
    TracedRays trace(const std::vector<gpu::RayItem>& rays, uint32_t repeats = 1, bool count_on_device = true);

    // Traces shadow rays (ShadowRayItem: origin, direction, t_max, origin_triangle in BVH leaf order; path and
    // contribution are set here) through the connect stage, as a render's next-event estimation does, `repeats` times.
    // Each ray i adds a contribution of 1 to path i's radiance where it is not occluded; that radiance is read back.
    TracedShadowRays trace_shadow_rays(const std::vector<gpu::ShadowRayItem>& rays, uint32_t repeats = 1);

private:
    const vk::Context& context_;
    uint32_t capacity_;
    StageTable stages_;
    GpuBuffers buffers_;
};

}  // namespace fh
