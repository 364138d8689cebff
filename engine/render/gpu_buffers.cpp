// Allocates and fills the device buffers; empty arrays get one dummy element (Vulkan has no empty buffers).
#include "render/gpu_buffers.h"

#include <cstring>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <vector>

#include "render/memory_estimate.h"
#include "vk/context.h"
#include "vk/pipeline.h"

namespace fh {
namespace tables {
#include "lib/tables/ggx_albedo_table.glsl"
#include "lib/tables/sheen_albedo_table.glsl"
#include "lib/tables/spectral_table.glsl"
#include "lib/tables/glass_albedo_table.glsl"
#include "lib/tables/ggx_anisotropic_albedo_table.glsl"
}  // namespace tables
namespace {

// Tables one after the other, as one buffer's words.
std::vector<float> concatenate(std::initializer_list<std::span<const float>> parts) {
    std::vector<float> words;
    for (const std::span<const float>& part : parts) words.insert(words.end(), part.begin(), part.end());
    return words;
}

// The GGX albedo table in the order shaders/lib/tables/ggx_albedo_table.glsl documents, then the sheen lobe's, then the
// spectral path's (bindings.glsl reads all three from one uniform buffer).
std::vector<float> flatten_albedo_tables() {
    return concatenate({tables::GGX_ALBEDO_A, tables::GGX_ALBEDO_B, tables::GGX_ALBEDO_AVERAGE_A,
                        tables::GGX_ALBEDO_AVERAGE_B, tables::SHEEN_ALBEDO, tables::SPECTRAL_TABLE});
}

// The glass albedo table in the order shaders/lib/tables/glass_albedo_table.glsl documents (EFFECT_GLASS_MULTISCATTER),
// else one word.
std::vector<float> flatten_glass_albedo_table(EffectBits effects) {
    if (!(effects & gpu::EFFECT_GLASS_MULTISCATTER)) return {0.0f};
    return concatenate({tables::GLASS_ALBEDO_OUT, tables::GLASS_ALBEDO_IN, tables::GLASS_ALBEDO_AVERAGE_OUT,
                        tables::GLASS_ALBEDO_AVERAGE_IN, tables::GLASS_ALBEDO_K, tables::GLASS_ALBEDO_F_AVERAGE});
}

// The white anisotropic GGX lobe's albedo table in the order shaders/lib/tables/ggx_anisotropic_albedo_table.glsl
// documents (anisotropic_albedo_bytes says when), else one word.
std::vector<float> flatten_anisotropic_albedo_table(EffectBits effects) {
    if (anisotropic_albedo_bytes(effects) == sizeof(float)) return {0.0f};
    return concatenate({tables::GGX_ANISOTROPIC_ALBEDO, tables::GGX_ANISOTROPIC_ALBEDO_AVERAGE});
}

constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

template <typename T>
vk::Buffer make_buffer(const vk::Context& context, const std::vector<T>& items, VkBufferUsageFlags usage) {
    size_t size = std::max<size_t>(items.size(), 1) * sizeof(T);
    vk::Buffer buffer(context, size, usage, vk::MemoryUse::device);
    if (!items.empty()) vk::upload_to_buffer(context, buffer, items.data(), items.size() * sizeof(T));
    return buffer;
}

template <typename T>
vk::Buffer make_filled_buffer(const vk::Context& context, const std::vector<T>& items) {
    return make_buffer(context, items, STORAGE);
}

// The images' RGBA8 texels, four to an RGBA32UI texel: zeros after the last to fill it.
std::vector<gpu::uvec4> pad_to_texels(const std::vector<uint32_t>& texels) {
    std::vector<gpu::uvec4> packed((texels.size() + 3) / 4, gpu::uvec4(0u));
    if (!texels.empty()) std::memcpy(packed.data(), texels.data(), texels.size() * sizeof(uint32_t));
    return packed;
}

// A scene array read as RGBA32UI texels (layout.h TEXELS bindings): whole texels per element.
template <typename T>
vk::Buffer make_texel_buffer(const vk::Context& context, const std::vector<T>& items) {
    static_assert(sizeof(T) % gpu::TEXEL_BYTES == 0, "a texel-buffer struct is whole 16-byte texels");
    return make_buffer(context, items, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT);
}

vk::Buffer make_state_buffer(const vk::Context& context, size_t size, VkBufferUsageFlags extra = 0) {
    return vk::Buffer(context, size, STORAGE | extra, vk::MemoryUse::device);
}

// Attributes of a triangle without any: texture coordinates 0, COLOR_0 white, no tangent.
gpu::TriangleAttributes make_default_attributes() {
    gpu::TriangleAttributes a{};
    const uint32_t white = 0x3c003c00u;  // two half-float 1.0s
    a.color0_rg = a.color0_ba = a.color1_rg = a.color1_ba = a.color2_rg = a.color2_ba = white;
    return a;
}

}  // namespace

GpuBuffers create_gpu_buffers(const vk::Context& context, const PackedScene& scene, const gpu::FrameParams& frame,
                              EffectBits effects, const PathStore& store) {
    GpuBuffers b;
    b.params = make_buffer(context, std::vector<gpu::FrameParams>{frame}, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    b.nodes = make_texel_buffer(context, scene.nodes);
    b.tri_positions = make_texel_buffer(context, scene.positions);
    b.tri_shading = make_texel_buffer(context, scene.shading);
    b.materials = make_texel_buffer(context, scene.materials);
    b.emitters = make_texel_buffer(context, scene.emitters);
    b.punctual_lights = make_texel_buffer(context, scene.punctual_lights);
    b.light_tree = make_texel_buffer(context, scene.light_tree);
    b.ggx_albedo = make_buffer(context, flatten_albedo_tables(), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    const size_t capacity = frame.wave_capacity;
    b.counters = make_state_buffer(context, sizeof(gpu::QueueCounters), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
    b.counters_readback = vk::Buffer(context, sizeof(gpu::QueueCounters), STORAGE, vk::MemoryUse::host);
    // Also read as texels by the stage after the one that writes them (layout.h BINDING_PATH_TEXELS ...).
    constexpr VkBufferUsageFlags TEXELS = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    b.paths = make_state_buffer(context, capacity * sizeof(gpu::PathState), TEXELS);
    b.rays = make_state_buffer(context, 2 * capacity * sizeof(gpu::RayItem), TEXELS);
    b.hits = make_state_buffer(context, capacity * sizeof(gpu::HitItem), TEXELS);
    b.shadow_rays = make_state_buffer(context, capacity * sizeof(gpu::ShadowRayItem), TEXELS);
    b.film = make_state_buffer(context, size_t(frame.film_width) * frame.film_height * sizeof(gpu::FilmPixel));
    // --force-effect of an attribute effect on a scene without attributes: the stages read defaults.
    if (scene.attributes.empty() && (effects & ATTRIBUTE_EFFECTS))
        b.tri_attributes = make_texel_buffer(
            context, std::vector<gpu::TriangleAttributes>(std::max<size_t>(scene.positions.size(), 1),
                                                          make_default_attributes()));
    else
        b.tri_attributes = make_texel_buffer(context, scene.attributes);
    b.texture_slots = make_texel_buffer(context, scene.texture_slots);
    b.texture_images = make_texel_buffer(context, scene.texture_images);
    b.texels = make_texel_buffer(context, pad_to_texels(scene.texels));
    b.env_radiance = make_filled_buffer(context, scene.environment.texels);
    b.env_cdf = make_filled_buffer(context, scene.environment.cdf);
    b.instances = make_texel_buffer(context, scene.instances);
    b.material_layers = make_texel_buffer(context, scene.material_layers);
    b.path_media = make_state_buffer(context, path_media_bytes(frame.wave_capacity, effects));
    b.path_light_points = make_state_buffer(context, path_light_points_bytes(frame.wave_capacity, effects));
    b.path_aovs = make_state_buffer(context, path_aovs_bytes(frame.wave_capacity, store));
    b.aov_film = make_state_buffer(context, aov_film_bytes(frame.film_width, frame.film_height, store));
    b.pixel_list = make_state_buffer(context, pixel_list_bytes(frame.film_width, frame.film_height, store));
    b.pixel_work = make_state_buffer(context, pixel_list_bytes(frame.film_width, frame.film_height, store));
    b.path_work = make_state_buffer(context, path_work_bytes(frame.wave_capacity, store));
    b.path_spectra = make_state_buffer(context, path_spectra_bytes(frame.wave_capacity, effects));
    b.path_times = make_state_buffer(context, path_times_bytes(frame.wave_capacity, effects));
    b.glass_albedo = make_filled_buffer(context, flatten_glass_albedo_table(effects));
    b.anisotropic_albedo = make_filled_buffer(context, flatten_anisotropic_albedo_table(effects));
    b.light_vertices = make_state_buffer(context, light_vertices_bytes(frame.wave_capacity, store));
    b.path_mis = make_state_buffer(context, path_mis_bytes(frame.wave_capacity, store));
    b.merge_points = make_state_buffer(context, merge_points_bytes(frame.wave_capacity, store));
    b.path_dvm = make_state_buffer(context, path_dvm_bytes(frame.wave_capacity, store));
    b.merge_grid = make_state_buffer(context, merge_grid_bytes(frame.wave_capacity, store));
    // Outside every volume until the renderer has probed the lights (render/light_media.h).
    const size_t lights = light_media_bytes(scene, effects, store) / sizeof(gpu::uvec4);
    b.light_media = make_filled_buffer(context, std::vector<gpu::uvec4>(lights, gpu::uvec4(gpu::INVALID_INDEX)));
    // bin_rays counts into zeros; scan_ray_bins leaves them zero again.
    b.ray_sort = make_filled_buffer(context, std::vector<uint32_t>(ray_sort_bytes(frame.wave_capacity, store) / 4, 0u));
    // The limits check before rendering relies on the estimate: keep it exact.
    uint64_t allocated = 0;
    for (const vk::Buffer* buffer : {&b.params, &b.nodes, &b.tri_positions, &b.tri_shading, &b.materials, &b.emitters,
                                     &b.punctual_lights, &b.ggx_albedo, &b.counters, &b.counters_readback, &b.paths, &b.rays, &b.hits,
                                     &b.shadow_rays, &b.film, &b.tri_attributes, &b.texture_slots, &b.texture_images,
                                     &b.texels, &b.env_radiance, &b.env_cdf, &b.instances, &b.material_layers, &b.path_media,
                                     &b.path_spectra, &b.path_times, &b.glass_albedo, &b.anisotropic_albedo, &b.light_vertices, &b.path_mis, &b.ray_sort,
                                     &b.light_tree, &b.path_light_points, &b.path_aovs, &b.aov_film, &b.pixel_list, &b.pixel_work,
                                     &b.path_work, &b.light_media, &b.merge_points, &b.path_dvm, &b.merge_grid})
        allocated += buffer->size();
    if (allocated !=
        estimate_render_memory(scene, frame.film_width, frame.film_height, frame.wave_capacity, effects, store).device_bytes())
        throw std::logic_error("create_gpu_buffers: allocated sizes differ from estimate_render_memory");
    return b;
}

void bind_gpu_buffers(vk::BindingTable& table, const GpuBuffers& b) {
    table.bind_buffer(gpu::BINDING_PARAMS, b.params);
    table.bind_buffer(gpu::BINDING_BVH_NODES, b.nodes);
    table.bind_buffer(gpu::BINDING_TRI_POSITIONS, b.tri_positions);
    table.bind_buffer(gpu::BINDING_TRI_SHADING, b.tri_shading);
    table.bind_buffer(gpu::BINDING_MATERIALS, b.materials);
    table.bind_buffer(gpu::BINDING_EMITTERS, b.emitters);
    table.bind_buffer(gpu::BINDING_COUNTERS, b.counters);
    table.bind_buffer(gpu::BINDING_PATHS, b.paths);
    table.bind_buffer(gpu::BINDING_RAYS, b.rays);
    table.bind_buffer(gpu::BINDING_HITS, b.hits);
    table.bind_buffer(gpu::BINDING_SHADOW_RAYS, b.shadow_rays);
    table.bind_buffer(gpu::BINDING_PATH_TEXELS, b.paths);
    table.bind_buffer(gpu::BINDING_RAY_TEXELS, b.rays);
    table.bind_buffer(gpu::BINDING_HIT_TEXELS, b.hits);
    table.bind_buffer(gpu::BINDING_SHADOW_RAY_TEXELS, b.shadow_rays);
    table.bind_buffer(gpu::BINDING_FILM, b.film);
    table.bind_buffer(gpu::BINDING_GGX_ALBEDO_UNIFORM, b.ggx_albedo);
    table.bind_buffer(gpu::BINDING_PUNCTUAL_LIGHTS, b.punctual_lights);
    table.bind_buffer(gpu::BINDING_TRI_ATTRIBUTES, b.tri_attributes);
    table.bind_buffer(gpu::BINDING_TEXTURE_SLOTS, b.texture_slots);
    table.bind_buffer(gpu::BINDING_TEXTURE_IMAGES, b.texture_images);
    table.bind_buffer(gpu::BINDING_TEXELS, b.texels);
    table.bind_buffer(gpu::BINDING_ENV_RADIANCE, b.env_radiance);
    table.bind_buffer(gpu::BINDING_ENV_CDF, b.env_cdf);
    table.bind_buffer(gpu::BINDING_INSTANCES, b.instances);
    table.bind_buffer(gpu::BINDING_MATERIAL_LAYERS, b.material_layers);
    table.bind_buffer(gpu::BINDING_PATH_MEDIA, b.path_media);
    table.bind_buffer(gpu::BINDING_PATH_SPECTRA, b.path_spectra);
    table.bind_buffer(gpu::BINDING_PATH_TIMES, b.path_times);
    table.bind_buffer(gpu::BINDING_LIGHT_VERTICES, b.light_vertices);
    table.bind_buffer(gpu::BINDING_PATH_MIS, b.path_mis);
    table.bind_buffer(gpu::BINDING_MERGE_POINTS, b.merge_points);
    table.bind_buffer(gpu::BINDING_PATH_DVM, b.path_dvm);
    table.bind_buffer(gpu::BINDING_MERGE_GRID, b.merge_grid);
    table.bind_buffer(gpu::BINDING_RAY_SORT, b.ray_sort);
    table.bind_buffer(gpu::BINDING_GLASS_ALBEDO, b.glass_albedo);
    table.bind_buffer(gpu::BINDING_ANISOTROPIC_ALBEDO, b.anisotropic_albedo);
    table.bind_buffer(gpu::BINDING_LIGHT_TREE, b.light_tree);
    table.bind_buffer(gpu::BINDING_PATH_LIGHT_POINTS, b.path_light_points);
    table.bind_buffer(gpu::BINDING_PATH_AOVS, b.path_aovs);
    table.bind_buffer(gpu::BINDING_AOV_FILM, b.aov_film);
    table.bind_buffer(gpu::BINDING_PIXEL_LIST, b.pixel_list);
    table.bind_buffer(gpu::BINDING_PIXEL_WORK, b.pixel_work);
    table.bind_buffer(gpu::BINDING_PATH_WORK, b.path_work);
    table.bind_buffer(gpu::BINDING_LIGHT_MEDIA, b.light_media);
}

}  // namespace fh
