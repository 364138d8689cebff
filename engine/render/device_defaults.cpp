#include "render/device_defaults.h"

#include <algorithm>

#include "scene/effects.h"
#include "vk/context.h"

namespace fh {

uint32_t choose_wave_paths(bool cpu_device, const DeviceMemoryLimits& limits, const PackedScene& scene,
                           EffectBits effects, uint32_t film_width, uint32_t film_height, const PathStore& store) {
    const double per_path = bytes_per_path(scene, effects, store);
    uint32_t paths = cpu_device ? CPU_WAVE_PATHS : GPU_WAVE_PATHS;
    for (;; paths /= 2) {
        const bool buffers_fit =
            find_memory_problem(estimate_render_memory(scene, film_width, film_height, paths, effects, store), limits).empty();
        const bool quarter = limits.device_local_heap == 0 || per_path * paths <= 0.25 * double(limits.device_local_heap);
        if (buffers_fit && quarter) break;
        if (paths <= MIN_AUTO_WAVE_PATHS && (buffers_fit || paths <= MIN_FITTING_WAVE_PATHS)) break;
    }
    return paths;
}

bool is_cpu_device(const vk::Context& context) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(context.physical_device(), &properties);
    return properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

uint32_t choose_wave_paths(const vk::Context& context, const PackedScene& scene, EffectBits effects,
                           uint32_t film_width, uint32_t film_height, const PathStore& store, uint64_t memory_limit) {
    DeviceMemoryLimits limits = query_memory_limits(context);
    if (memory_limit > 0) limits.device_local_heap = std::min(limits.device_local_heap, memory_limit);
    return choose_wave_paths(is_cpu_device(context), limits, scene, effects, film_width, film_height, store);
}

bool choose_sort_rays(bool cpu_device, const PackedScene& scene) {
    return !cpu_device && scene.positions.size() >= MIN_AUTO_SORT_TRIANGLES;
}

RenderSettings with_device_defaults(RenderSettings settings, const vk::Context& context, const PackedScene& scene) {
    if (!settings.sort_rays) settings.sort_rays = choose_sort_rays(is_cpu_device(context), scene);
    if (settings.wave_paths == 0)
        settings.wave_paths = choose_wave_paths(
            context, scene, select_effects(scene.effects.bits, settings.forced_effects, settings.disabled_effects),
            settings.film_width(), settings.film_height(), make_path_store(settings), settings.resolved_memory_limit());
    return settings;
}

}  // namespace fh
