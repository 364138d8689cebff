// Device memory a render needs, from the packed scene and the film and wave sizes, against the device's limits.
#include "render/memory_estimate.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "render/light_tracing.h"
#include "render/vertex_merging.h"
#include "vk/context.h"

namespace fh {
namespace tables {
#include "lib/tables/ggx_albedo_table.glsl"
#include "lib/tables/sheen_albedo_table.glsl"
#include "lib/tables/spectral_table.glsl"
#include "lib/tables/glass_albedo_table.glsl"
#include "lib/tables/ggx_anisotropic_albedo_table.glsl"
}  // namespace tables
namespace {

template <typename T>
uint64_t array_bytes(const std::vector<T>& items) {
    return std::max<uint64_t>(items.size(), 1) * sizeof(T);
}

}  // namespace

uint64_t MemoryEstimate::device_bytes() const {
    uint64_t total = 0;
    for (const BufferEstimate& b : buffers) total += b.bytes;
    return total;
}

uint64_t attribute_bytes(const PackedScene& scene, EffectBits effects) {
    if (scene.attributes.empty() && (effects & ATTRIBUTE_EFFECTS))
        return std::max<uint64_t>(scene.positions.size(), 1) * sizeof(gpu::TriangleAttributes);
    return array_bytes(scene.attributes);
}

uint64_t path_media_bytes(uint32_t wave_capacity, EffectBits effects) {
    return (effects & (gpu::EFFECT_VOLUME | gpu::EFFECT_ABSORPTION))
               ? uint64_t(wave_capacity) * gpu::MEDIUM_STACK_SIZE * sizeof(uint32_t)
               : gpu::MEDIUM_STACK_SIZE * sizeof(uint32_t);
}

uint64_t path_light_points_bytes(uint32_t wave_capacity, EffectBits effects) {
    return uint64_t((effects & gpu::EFFECT_LIGHT_TREE) ? wave_capacity : 1u) * sizeof(gpu::uvec4);
}

uint64_t glass_albedo_bytes(EffectBits effects) {
    return uint64_t((effects & gpu::EFFECT_GLASS_MULTISCATTER) ? tables::GLASS_ALBEDO_TABLE_SIZE : 1) * sizeof(float);
}

uint64_t anisotropic_albedo_bytes(EffectBits effects) {
    const EffectBits both = gpu::EFFECT_ANISOTROPY | gpu::EFFECT_GGX_MULTISCATTER;
    return uint64_t((effects & both) == both ? tables::GGX_ANISOTROPIC_ALBEDO_TABLE_SIZE : 1) * sizeof(float);
}

uint64_t path_times_bytes(uint32_t wave_capacity, EffectBits effects) {
    return uint64_t((effects & gpu::EFFECT_MOTION_BLUR) ? wave_capacity : 1u) * sizeof(float);
}

uint64_t path_spectra_bytes(uint32_t wave_capacity, EffectBits effects) {
    return uint64_t((effects & gpu::EFFECT_SPECTRAL) ? wave_capacity : 1u) * sizeof(gpu::PathSpectrum);
}

PathStore make_path_store(const RenderSettings& settings) {
    PathStore b;
    b.bdpt = connects_subpaths(settings.integrator);
    b.vcm = settings.integrator == Integrator::vcm;
    b.light_subpaths = settings.integrator == Integrator::light || b.bdpt;
    b.light_vertex_slots = count_light_vertex_slots(settings);
    b.sort_rays = settings.sort_rays.value_or(false);  // resolved by with_device_defaults before any estimate
    b.aovs = settings.aovs;
    b.pixel_list = settings.adaptive;
    return b;
}

uint64_t pixel_list_bytes(uint32_t width, uint32_t height, const PathStore& store) {
    return (store.pixel_list ? uint64_t(width) * height : 1u) * sizeof(uint32_t);
}

uint64_t path_work_bytes(uint32_t wave_capacity, const PathStore& store) {
    return uint64_t(store.pixel_list ? wave_capacity : 1u) * sizeof(uint32_t);
}

uint64_t path_aovs_bytes(uint32_t wave_capacity, const PathStore& store) {
    return uint64_t(store.aovs ? wave_capacity : 1u) * sizeof(gpu::PathAov);
}

uint64_t aov_film_bytes(uint32_t width, uint32_t height, const PathStore& store) {
    return (store.aovs ? uint64_t(width) * height : 1u) * sizeof(gpu::AovPixel);
}

uint64_t ray_sort_bytes(uint32_t wave_capacity, const PathStore& store) {
    return store.sort_rays
               ? (uint64_t(gpu::RAY_SORT_FIXED_WORDS) + uint64_t(gpu::RAY_SORT_WORDS_PER_RAY) * wave_capacity) *
                     sizeof(uint32_t)
               : sizeof(uint32_t);
}

uint64_t light_vertices_bytes(uint32_t wave_capacity, const PathStore& store) {
    return std::max<uint64_t>(store.bdpt ? uint64_t(wave_capacity) * store.light_vertex_slots : 1, 1) *
           sizeof(gpu::LightVertex);
}

uint64_t light_media_bytes(const PackedScene& scene, EffectBits effects, const PathStore& store) {
    const bool probed = store.light_subpaths && (effects & gpu::EFFECT_VOLUME);
    return std::max<uint64_t>(probed ? scene.emitters.size() : 1, 1) * sizeof(gpu::uvec4);
}

uint64_t path_mis_bytes(uint32_t wave_capacity, const PathStore& store) {
    return uint64_t(store.bdpt ? wave_capacity : 1u) * sizeof(gpu::PathMis);
}

uint64_t merge_points_bytes(uint32_t wave_capacity, const PathStore& store) {
    return std::max<uint64_t>(store.vcm ? uint64_t(wave_capacity) * store.light_vertex_slots : 1, 1) * 4 * sizeof(float);
}

uint64_t path_dvm_bytes(uint32_t wave_capacity, const PathStore& store) {
    return uint64_t(store.vcm ? wave_capacity : 1u) * sizeof(float);
}

uint64_t merge_grid_bytes(uint32_t wave_capacity, const PathStore& store) {
    if (!store.vcm) return sizeof(uint32_t);
    return (2 * uint64_t(count_merge_grid_cells(wave_capacity, store.light_vertex_slots)) +
            uint64_t(wave_capacity) * store.light_vertex_slots) * sizeof(uint32_t);
}

MemoryEstimate estimate_render_memory(const PackedScene& scene, uint32_t width, uint32_t height,
                                      uint32_t wave_capacity, EffectBits effects, const PathStore& store) {
    const uint64_t capacity = wave_capacity;
    const uint64_t film = uint64_t(width) * height * sizeof(gpu::FilmPixel);
    MemoryEstimate e;
    const BufferBinding storage = BufferBinding::storage, texels = BufferBinding::texels, other = BufferBinding::other,
                        both = BufferBinding::storage_and_texels;
    e.buffers = {
        {"params", sizeof(gpu::FrameParams), other},  // a uniform buffer of a few hundred bytes
        {"nodes", array_bytes(scene.nodes), texels},
        {"tri_positions", array_bytes(scene.positions), texels},
        {"tri_shading", array_bytes(scene.shading), texels},
        {"materials", array_bytes(scene.materials), texels},
        {"emitters", array_bytes(scene.emitters), texels},
        {"punctual_lights", array_bytes(scene.punctual_lights), texels},
        {"light_tree", array_bytes(scene.light_tree), texels},
        {"albedo_tables", uint64_t(tables::GGX_ALBEDO_TABLE_SIZE + tables::SHEEN_ALBEDO_TABLE_SIZE + tables::SPECTRAL_TABLE_SIZE) * sizeof(float), other},
        {"counters", sizeof(gpu::QueueCounters), storage},
        {"counters_readback", sizeof(gpu::QueueCounters), storage},
        {"paths", capacity * sizeof(gpu::PathState), both},
        {"rays", 2 * capacity * sizeof(gpu::RayItem), both},
        {"hits", capacity * sizeof(gpu::HitItem), both},
        {"shadow_rays", capacity * sizeof(gpu::ShadowRayItem), both},
        {"film", film, storage},
        {"tri_attributes", attribute_bytes(scene, effects), texels},
        {"texture_slots", array_bytes(scene.texture_slots), texels},
        {"texture_images", array_bytes(scene.texture_images), texels},
        {"texels", std::max<uint64_t>((scene.texels.size() + 3) / 4, 1) * gpu::TEXEL_BYTES, texels},
        {"env_radiance", array_bytes(scene.environment.texels), storage},
        {"env_cdf", array_bytes(scene.environment.cdf), storage},
        {"instances", array_bytes(scene.instances), texels},
        {"material_layers", array_bytes(scene.material_layers), texels},
        {"path_media", path_media_bytes(wave_capacity, effects), storage},
        {"path_spectra", path_spectra_bytes(wave_capacity, effects), storage},
        {"path_times", path_times_bytes(wave_capacity, effects), storage},
        {"glass_albedo", glass_albedo_bytes(effects), storage},
        {"anisotropic_albedo", anisotropic_albedo_bytes(effects), storage},
        {"light_vertices", light_vertices_bytes(wave_capacity, store), storage},
        {"path_mis", path_mis_bytes(wave_capacity, store), storage},
        {"merge_points", merge_points_bytes(wave_capacity, store), storage},
        {"path_dvm", path_dvm_bytes(wave_capacity, store), storage},
        {"merge_grid", merge_grid_bytes(wave_capacity, store), storage},
        {"light_media", light_media_bytes(scene, effects, store), storage},
        {"ray_sort", ray_sort_bytes(wave_capacity, store), storage},
        {"path_light_points", path_light_points_bytes(wave_capacity, effects), storage},
        {"path_aovs", path_aovs_bytes(wave_capacity, store), storage},
        {"aov_film", aov_film_bytes(width, height, store), storage},
        {"pixel_list", pixel_list_bytes(width, height, store), storage},
        {"pixel_work", pixel_list_bytes(width, height, store), storage},
        {"path_work", path_work_bytes(wave_capacity, store), storage},
    };
    e.film_readback_bytes = film;
    return e;
}

MemoryEstimate estimate_render_memory(const PackedScene& scene, const RenderSettings& s) {
    if (s.wave_paths == 0) throw std::logic_error("estimate_render_memory: wave_paths not chosen (with_device_defaults)");
    const uint64_t samples = uint64_t(s.film_width()) * s.film_height() * s.spp;
    return estimate_render_memory(scene, s.film_width(), s.film_height(), uint32_t(std::min<uint64_t>(s.wave_paths, samples)),
                                  select_effects(scene.effects.bits, s.forced_effects, s.disabled_effects),
                                  make_path_store(s));
}

DeviceMemoryLimits query_memory_limits(const vk::Context& context) {
    DeviceMemoryLimits limits;
    VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &maintenance3;
    vkGetPhysicalDeviceProperties2(context.physical_device(), &properties);
    limits.max_storage_buffer_range = properties.properties.limits.maxStorageBufferRange;
    limits.max_texel_buffer_elements = properties.properties.limits.maxTexelBufferElements;
    limits.max_allocation_size = maintenance3.maxMemoryAllocationSize;
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(context.physical_device(), &memory);
    for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
        if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            limits.device_local_heap = std::max<uint64_t>(limits.device_local_heap, memory.memoryHeaps[i].size);
    return limits;
}

namespace {
// What to change when a buffer is too large (buffers are not split across allocations yet).
std::string remedy(const std::string& buffer) {
    std::string what = "a smaller scene";
    if (buffer == "film") what = "a smaller --width/--height (or --crop parts joined by fredholm merge)";
    if (buffer == "texels") what = "smaller textures";
    if (buffer == "env_radiance" || buffer == "env_cdf") what = "a smaller environment map";
    if (buffer == "paths" || buffer == "rays" || buffer == "hits" || buffer == "shadow_rays" ||
        buffer == "light_vertices" || buffer == "path_mis" || buffer == "ray_sort" || buffer == "merge_points" ||
        buffer == "merge_grid" || buffer == "path_dvm")
        what = "a smaller --wave-paths";
    return "; Fredholm does not split buffers yet: use " + what;
}
}  // namespace

std::string find_memory_problem(const MemoryEstimate& estimate, const DeviceMemoryLimits& limits) {
    for (const BufferEstimate& b : estimate.buffers) {
        const std::string split_note = remedy(b.name);
        const bool storage = b.binding == BufferBinding::storage || b.binding == BufferBinding::storage_and_texels;
        const bool texels = b.binding == BufferBinding::texels || b.binding == BufferBinding::storage_and_texels;
        if (storage && b.bytes > limits.max_storage_buffer_range)
            return "the " + b.name + " buffer needs " + format_bytes(b.bytes) +
                   ", more than the device's maxStorageBufferRange of " +
                   format_bytes(limits.max_storage_buffer_range) + split_note;
        const uint64_t texel_limit = limits.max_texel_buffer_elements * gpu::TEXEL_BYTES;
        if (texels && b.bytes > texel_limit)
            return "the " + b.name + " buffer needs " + format_bytes(b.bytes) +
                   ", more than the device's maxTexelBufferElements of " +
                   std::to_string(limits.max_texel_buffer_elements) + " 16-byte texels (" + format_bytes(texel_limit) +
                   ")" + split_note;
        if (b.bytes > limits.max_allocation_size)
            return "the " + b.name + " buffer needs " + format_bytes(b.bytes) +
                   ", more than the device's maxMemoryAllocationSize of " + format_bytes(limits.max_allocation_size) +
                   split_note;
    }
    if (estimate.film_readback_bytes > limits.max_allocation_size)
        return "reading the film back needs a staging buffer of " + format_bytes(estimate.film_readback_bytes) +
               ", more than the device's maxMemoryAllocationSize of " + format_bytes(limits.max_allocation_size) +
               remedy("film");
    const uint64_t needed = estimate.device_bytes();
    if (limits.device_local_heap > 0 && needed > limits.device_local_heap) {
        const auto largest = std::max_element(estimate.buffers.begin(), estimate.buffers.end(),
                                              [](const auto& a, const auto& b) { return a.bytes < b.bytes; });
        return "the render needs " + format_bytes(needed) + " of device memory, more than the device-local heap of " +
               format_bytes(limits.device_local_heap) + " (largest: " + largest->name + ", " +
               format_bytes(largest->bytes) + ")";
    }
    return {};
}

std::vector<MemoryUse> host_render_uses(const Scene& scene, const MemoryEstimate& device) {
    const auto bytes = [](const auto& v) { return uint64_t(v.size()) * sizeof(v[0]); };
    uint64_t textures = 0;
    for (const SceneImage& image : scene.images) textures += bytes(image.texels);
    const uint64_t geometry = bytes(scene.positions) + bytes(scene.normals) + bytes(scene.triangle_material) +
                              bytes(scene.triangle_has_normals) + bytes(scene.texcoords0) + bytes(scene.texcoords1) +
                              bytes(scene.colors) + bytes(scene.tangents);
    uint64_t packed = 0;
    for (const BufferEstimate& b : device.buffers)
        if (b.binding == BufferBinding::texels || b.name.rfind("env_", 0) == 0) packed += b.bytes;
    return {{"host scene geometry", geometry}, {"host scene textures", textures}, {"host packed scene", packed},
            {"host film readback", device.film_readback_bytes}};
}

std::string find_memory_limit_problem(const std::vector<MemoryUse>& host, const MemoryEstimate& device, uint64_t limit,
                                      bool cpu_device) {
    std::vector<MemoryUse> device_uses;
    for (const BufferEstimate& b : device.buffers) device_uses.push_back({"device " + b.name, b.bytes});
    if (cpu_device) {
        std::vector<MemoryUse> all = host;
        all.insert(all.end(), device_uses.begin(), device_uses.end());
        return find_limit_problem(all, limit, "the render (host and device memory: one on a CPU device)");
    }
    const std::string problem = find_limit_problem(host, limit, "the render's host memory");
    return problem.empty() ? find_limit_problem(device_uses, limit, "the render's device memory") : problem;
}

void check_render_memory(const MemoryEstimate& estimate, const DeviceMemoryLimits& limits) {
    const std::string problem = find_memory_problem(estimate, limits);
    if (!problem.empty()) throw std::runtime_error(problem);
}

double bytes_per_path(const PackedScene& scene, EffectBits effects, const PathStore& store) {
    const auto bytes = [&](uint32_t capacity) {
        return estimate_render_memory(scene, 16, 16, capacity, effects, store).device_bytes();
    };
    return double(bytes(1u << 16) - bytes(1u << 15)) / double(1u << 15);
}

}  // namespace fh
