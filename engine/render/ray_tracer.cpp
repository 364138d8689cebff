// Runs the extend stage over a hand-made ray queue and reads the hits back (see ray_tracer.h).
#include "render/ray_tracer.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

#include "render/ray_sort.h"
#include "render/renderer.h"
#include "vk/buffer.h"
#include "vk/commands.h"
#include "vk/context.h"

namespace fh {
namespace {

gpu::FrameParams make_ray_frame(const PackedScene& scene, uint32_t capacity) {
    gpu::FrameParams frame{};
    frame.width = 1;
    frame.height = 1;
    frame.film_width = 1;
    frame.film_height = 1;
    frame.wave_capacity = capacity;
    frame.triangle_count = uint32_t(scene.positions.size());
    set_frame_scene_bounds(frame, scene);  // traversal pads its boxes from these
    return frame;
}

StageOptions make_ray_stage_options(const PackedScene& scene, bool sort_rays, EffectBits disabled_effects) {
    StageOptions options;
    options.sort_rays = sort_rays;
    options.effects = scene.effects.bits & ~EffectBits(gpu::EFFECT_MOTION_BLUR) & ~disabled_effects;  // rays at the shutter's centre
    options.instances = !scene.instances.empty();
    return options;
}

}  // namespace

RayTracer::RayTracer(const vk::Context& context, const PackedScene& scene, uint32_t capacity, bool sort_rays,
                     EffectBits disabled_effects)
    : context_(context),
      capacity_(capacity),
      stages_(context, make_ray_stage_options(scene, sort_rays, disabled_effects)),
      buffers_(create_gpu_buffers(context, scene, make_ray_frame(scene, capacity), stages_.options().effects,
                                  PathStore{.sort_rays = sort_rays})) {
    bind_gpu_buffers(stages_.bindings(), buffers_);
}

TracedRays trace_ray_queue(const vk::Context& context, const StageTable& stages, GpuBuffers& buffers,
                           const std::vector<gpu::RayItem>& rays, uint32_t repeats, bool count_on_device) {
    std::vector<gpu::RayItem> items = rays;
    for (size_t i = 0; i < items.size(); ++i) items[i].path = uint32_t(i);
    vk::upload_to_buffer(context, buffers.rays, items.data(), items.size() * sizeof(gpu::RayItem));
    TracedRays result;
    gpu::QueueCounters counters{};
    for (uint32_t r = 0; r < repeats; ++r) {
        counters = {};
        counters.ray_count[0] = uint32_t(rays.size());
        counters.extend_args = {uint32_t((rays.size() + gpu::WORKGROUP_SIZE - 1) / gpu::WORKGROUP_SIZE), 1, 1};
        vk::upload_to_buffer(context, buffers.counters, &counters, sizeof(counters));
        vk::CommandRecorder recorder(context, RAY_SORT_MAX_DISPATCHES + 1);  // the sort, extend
        recorder.begin();
        recorder.bind_table(stages.bindings());
        gpu::StagePush push{};
        if (stages.options().sort_rays) push.ray_order = gpu::RAY_ORDER_SORTED;
        push.count_escaped_rays = count_on_device ? 1u : 0u;  // in a render shade counts them; no shade runs here
        recorder.push_constants(&push, sizeof(push));
        if (stages.options().sort_rays) record_ray_sort(recorder, stages, buffers);
        recorder.barrier_compute();
        recorder.dispatch_indirect(stages[Stage::extend], buffers.counters, offsetof(gpu::QueueCounters, extend_args));
        recorder.submit_and_wait();
        double seconds = 0.0;
        for (const auto& [name, dispatch] : recorder.dispatch_seconds()) seconds += dispatch;
        result.seconds.push_back(seconds);
    }
    result.hits.resize(rays.size());
    vk::download_from_buffer(context, buffers.hits, result.hits.data(), rays.size() * sizeof(gpu::HitItem));
    if (count_on_device) {
        vk::download_from_buffer(context, buffers.counters, &counters, sizeof(counters));
        result.escaped_rays = counters.escaped_rays;
    } else {
        result.escaped_rays = uint32_t(std::count_if(result.hits.begin(), result.hits.end(), [](const gpu::HitItem& h) {
            return h.triangle == gpu::INVALID_INDEX;
        }));
    }
    return result;
}

TracedShadowRays RayTracer::trace_shadow_rays(const std::vector<gpu::ShadowRayItem>& rays, uint32_t repeats) {
    if (rays.empty() || rays.size() > capacity_)
        throw std::invalid_argument("RayTracer: " + std::to_string(rays.size()) + " shadow rays for a capacity of " +
                                    std::to_string(capacity_));
    std::vector<gpu::ShadowRayItem> items = rays;
    for (size_t i = 0; i < items.size(); ++i) {
        items[i].path = uint32_t(i);
        items[i].contrib_r = 1.0f;
        items[i].contrib_g = items[i].contrib_b = 0.0f;
    }
    vk::upload_to_buffer(context_, buffers_.shadow_rays, items.data(), items.size() * sizeof(gpu::ShadowRayItem));
    TracedShadowRays result;
    for (uint32_t r = 0; r < repeats; ++r) {
        gpu::QueueCounters counters{};
        counters.shadow_count_active = uint32_t(rays.size());
        counters.connect_args = {uint32_t((rays.size() + gpu::WORKGROUP_SIZE - 1) / gpu::WORKGROUP_SIZE), 1, 1};
        vk::upload_to_buffer(context_, buffers_.counters, &counters, sizeof(counters));
        vk::CommandRecorder recorder(context_, 1);
        recorder.begin();
        recorder.fill_buffer(buffers_.paths, 0u);  // every path's radiance 0 (its rng 0: the alpha test's key)
        recorder.barrier_compute();
        recorder.bind_table(stages_.bindings());
        gpu::StagePush push{};
        recorder.push_constants(&push, sizeof(push));
        recorder.dispatch_indirect(stages_[Stage::connect], buffers_.counters, offsetof(gpu::QueueCounters, connect_args));
        recorder.submit_and_wait();
        double seconds = 0.0;
        for (const auto& [name, dispatch] : recorder.dispatch_seconds()) seconds += dispatch;
        result.seconds.push_back(seconds);
    }
    std::vector<gpu::PathState> paths(rays.size());
    vk::download_from_buffer(context_, buffers_.paths, paths.data(), paths.size() * sizeof(gpu::PathState));
    result.occluded.resize(rays.size());
    for (size_t i = 0; i < paths.size(); ++i) result.occluded[i] = paths[i].radiance_r == 0.0f ? 1u : 0u;
    return result;
}

TracedRays RayTracer::trace(const std::vector<gpu::RayItem>& rays, uint32_t repeats, bool count_on_device) {
    if (rays.empty() || rays.size() > capacity_)
        throw std::invalid_argument("RayTracer: " + std::to_string(rays.size()) + " rays for a capacity of " +
                                    std::to_string(capacity_));
    return trace_ray_queue(context_, stages_, buffers_, rays, repeats, count_on_device);
}

}  // namespace fh
