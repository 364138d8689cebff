// What a render will allocate on the device, checked against the device's limits before anything is allocated.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "render/settings.h"
#include "scene/memory_limit.h"
#include "scene/pack.h"

namespace fh {

namespace vk {
class Context;
}

// How a buffer is bound, which decides the limit its size must keep to.
enum class BufferBinding {
    storage,  // maxStorageBufferRange
    texels,   // a uniform texel buffer of 16-byte texels: maxTexelBufferElements texels
    storage_and_texels,  // both (the wave's arrays: written as storage, read as texels): both limits
    other,    // only maxMemoryAllocationSize (the uniform buffers: FrameParams, the albedo tables; host copies)
};

struct BufferEstimate {
    std::string name;    // as in GpuBuffers (e.g. "film", "tri_positions")
    uint64_t bytes = 0;
    BufferBinding binding = BufferBinding::storage;
};

struct MemoryEstimate {
    std::vector<BufferEstimate> buffers;  // every buffer create_gpu_buffers allocates, device-local
    uint64_t film_readback_bytes = 0;     // the host-visible staging copy read_film_state makes (at the end)
    uint64_t device_bytes() const;        // sum over buffers
};

// The device limits that decide whether a render fits.
struct DeviceMemoryLimits {
    uint64_t max_storage_buffer_range = 0;   // VkPhysicalDeviceLimits::maxStorageBufferRange
    uint64_t max_allocation_size = 0;        // VkPhysicalDeviceMaintenance3Properties::maxMemoryAllocationSize
    uint64_t device_local_heap = 0;          // the largest DEVICE_LOCAL heap (vkGetPhysicalDeviceMemoryProperties)
    uint64_t max_texel_buffer_elements = 0;  // VkPhysicalDeviceLimits::maxTexelBufferElements
};

// Sizes exactly as create_gpu_buffers makes them (empty arrays get one element); create_gpu_buffers checks
// that it allocates exactly this much, so the two cannot drift apart.
// `effects`: the EFFECT_* set the stages are compiled with (scene/effects.h select_effects).
// Bytes of the tri_attributes buffer: the scene's, or defaults for every triangle when `effects` read
// attributes the scene has none of (--force-effect); and of the path media and path spectra buffers.
uint64_t attribute_bytes(const PackedScene& scene, EffectBits effects);
uint64_t path_media_bytes(uint32_t wave_capacity, EffectBits effects);
// The shading point of each path's last NEE (EFFECT_LIGHT_TREE; else one element).
uint64_t path_light_points_bytes(uint32_t wave_capacity, EffectBits effects);
uint64_t path_spectra_bytes(uint32_t wave_capacity, EffectBits effects);
uint64_t path_times_bytes(uint32_t wave_capacity, EffectBits effects);  // EFFECT_MOTION_BLUR
// The glass albedo table's buffer: the whole table with EFFECT_GLASS_MULTISCATTER, else one word.
uint64_t glass_albedo_bytes(EffectBits effects);
// The anisotropic GGX lobe's albedo table: whole with EFFECT_ANISOTROPY and EFFECT_GGX_MULTISCATTER, else one word.
uint64_t anisotropic_albedo_bytes(EffectBits effects);

// What a path in flight keeps besides its state, by what the render does. Bidirectional path tracing: its MIS
// quantities (PathMis) and light_vertex_slots stored light-subpath vertices (LightVertex, render/light_tracing.h
// count_light_vertex_slots). The ray sort (render/ray_sort.h): a key, a rank and an order word per queued ray, and the key
// counts. Vertex merging: per light-vertex slot its point, per path its dvm, and the hash grid (render/vertex_merging.h).
// Off: one element each.
struct PathStore {
    bool bdpt = false;  // BDPT or VCM
    bool vcm = false;
    bool light_subpaths = false;  // light tracing or BDPT: with volumes, each light's media (light_media_bytes)
    uint32_t light_vertex_slots = 0;
    bool sort_rays = false;
    bool aovs = false;  // --aov: a PathAov per path and an AovPixel per pixel
    bool pixel_list = false;  // --adaptive: per pixel its place in the waves' order and its work, per path its work
};
PathStore make_path_store(const RenderSettings& settings);
uint64_t light_vertices_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t path_mis_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t merge_points_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t path_dvm_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t merge_grid_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t light_media_bytes(const PackedScene& scene, EffectBits effects, const PathStore& store);
uint64_t ray_sort_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t path_aovs_bytes(uint32_t wave_capacity, const PathStore& store);
uint64_t aov_film_bytes(uint32_t width, uint32_t height, const PathStore& store);
uint64_t pixel_list_bytes(uint32_t width, uint32_t height, const PathStore& store);  // also pixel_work's
uint64_t path_work_bytes(uint32_t wave_capacity, const PathStore& store);

MemoryEstimate estimate_render_memory(const PackedScene& scene, uint32_t width, uint32_t height,
                                      uint32_t wave_capacity, EffectBits effects, const PathStore& store = {});
// The same for a render with these settings (wave capacity as the Renderer picks it; wave_paths must be chosen:
// render/device_defaults.h with_device_defaults).
MemoryEstimate estimate_render_memory(const PackedScene& scene, const RenderSettings& settings);

DeviceMemoryLimits query_memory_limits(const vk::Context& context);

// Host memory a render keeps while it runs: the loaded scene's arrays and textures, and the packed copy its device
// buffers are filled from (the estimate's scene arrays: the texel-bound buffers and the environment's).
std::vector<MemoryUse> host_render_uses(const Scene& scene, const MemoryEstimate& device);

// The render against --memory-limit (`limit` bytes): on a CPU device, whose device memory is host memory, the host
// uses and the device buffers together; on a GPU, each against the limit. One line naming the largest uses, or empty.
std::string find_memory_limit_problem(const std::vector<MemoryUse>& host, const MemoryEstimate& device, uint64_t limit,
                                      bool cpu_device);

// One line naming the first buffer that breaks a limit (its size and the limit), or the total needed against the
// heap; empty when the render fits. Large scenes and films are refused, not split across buffers.
std::string find_memory_problem(const MemoryEstimate& estimate, const DeviceMemoryLimits& limits);
// Throws std::runtime_error with find_memory_problem's line when there is one.
void check_render_memory(const MemoryEstimate& estimate, const DeviceMemoryLimits& limits);

// Device bytes each path in flight adds (the wave's buffers: path state, queues, and the per-path arrays of
// `effects`), from the estimate at two wave sizes.
double bytes_per_path(const PackedScene& scene, EffectBits effects, const PathStore& store = {});

}  // namespace fh
