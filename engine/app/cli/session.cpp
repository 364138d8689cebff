// Scene preparation with timings, and Vulkan context creation for the command-line tools.
#include "app/cli/session.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <fstream>
#include <iterator>

#include "app/cli/progress.h"
#include "io/exr.h"
#include "render/device_defaults.h"
#include "render/memory_estimate.h"
#include "render/camera/camera_setup.h"
#include "scene/gltf/image_decode.h"
#include "shared/layout.h"

namespace fh {
namespace {
constexpr uint32_t MAX_TRAVERSAL_DEPTH = 64;  // BvhOptions::max_depth; the GPU stack itself: scene_bvh.cpp check_stack_bound
}  // namespace

BvhOptions make_bvh_options(const RenderSettings& settings) {
    BvhOptions options;
    options.max_leaf_size = settings.bvh_max_leaf_size;
    return options;
}

void apply_light_sampler(PreparedScene& prepared, const std::filesystem::path& file, const RenderSettings& settings) {
    try {
        choose_light_sampler(prepared.packed, settings.light_sampler, settings.integrator != Integrator::light);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(file.string() + ": --integrator " + to_string(settings.integrator) + ": " + e.what());
    }
}

PreparedScene prepare_scene(const std::filesystem::path& file, const RenderSettings& settings) {
    PreparedScene prepared;
    auto start = std::chrono::steady_clock::now();
    LoadOptions load;
    load.rebase = (settings.disabled_techniques & gpu::TECHNIQUE_REBASE) == 0;
    load.variant = settings.variant;
    load.instancing = settings.instancing;
    load.mikktspace_tangents = settings.tangents == Tangents::mikktspace;
    load.animate = settings.animate;
    load.animation = settings.animation;
    load.time = settings.time;
    load.shutter_open = settings.shutter_open;
    load.shutter_close = settings.shutter_close;
    load.memory_limit = settings.resolved_memory_limit();
    prepared.scene = load_gltf(file, load);
    prepared.load_seconds = seconds_since(start);
    for (const std::string& warning : prepared.scene.warnings)
        std::fprintf(stderr, "fredholm: warning: %s\n", warning.c_str());

    SceneBvh bvh = build_scene_bvh(prepared.scene, make_bvh_options(settings));
    if (bvh.max_depth >= MAX_TRAVERSAL_DEPTH)
        throw SceneError(file.string() + ": BVH depth " + std::to_string(bvh.max_depth) +
                         " exceeds the traversal stack (" + std::to_string(MAX_TRAVERSAL_DEPTH) + ")");
    prepared.bvh_build_seconds = bvh.build_seconds;
    prepared.sah_cost = bvh.sah_cost;
    prepared.wide_sah_cost = bvh.wide_sah_cost;
    prepared.bvh_nodes = bvh.node_count;
    prepared.bvh_depth = bvh.max_depth;
    prepared.packed = pack_scene(prepared.scene, bvh, load_environment(settings));
    // --integrator auto chooses by pilot renders first (render_command.cpp), then the light sampler.
    if (settings.integrator != Integrator::automatic) apply_light_sampler(prepared, file, settings);
    decide_camera_effects(prepared.packed.effects, settings.lens.on());
    decide_microfacet_effects(prepared.packed.effects, settings.microfacet == Microfacet::compensated);
    decide_motion_effects(prepared.packed.effects, settings.has_shutter(), prepared.scene.moving_instances,
                          choose_camera(prepared.scene, settings.camera).moves);
    return prepared;
}

namespace {
bool is_exr_file(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(file + ": cannot open the environment map");
    char magic[4] = {};
    in.read(magic, 4);
    return in.gcount() == 4 && std::memcmp(magic, "\x76\x2f\x31\x01", 4) == 0;
}

std::vector<unsigned char> read_bytes(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(file + ": cannot open the environment map");
    return std::vector<unsigned char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Refuses a map larger than the environment's limit from its declared size, before it is decoded.
void check_environment_size(const std::string& file, int64_t width, int64_t height) {
    if (width <= int64_t(MAX_ENVIRONMENT_WIDTH) && height <= int64_t(MAX_ENVIRONMENT_WIDTH / 2)) return;
    char gib[32];
    std::snprintf(gib, sizeof gib, "%.1f", double(width) * double(height) * 12.0 / double(1u << 30));
    throw IoError(file + ": environment map of " + std::to_string(width) + " x " + std::to_string(height) +
                  " texels declared (" + gib + " GiB as float RGB), more than the limit of " +
                  std::to_string(MAX_ENVIRONMENT_WIDTH) + " x " + std::to_string(MAX_ENVIRONMENT_WIDTH / 2));
}

// An OpenEXR or Radiance .hdr file, told apart by its magic bytes (not by its name).
Image read_environment_image(const std::string& file) {
    if (is_exr_file(file)) {
        const ImageSize size = read_exr_size(file);
        check_environment_size(file, size.width, size.height);
        return read_exr(file);
    }
    const std::vector<unsigned char> bytes = read_bytes(file);
    int64_t declared_width = 0, declared_height = 0;
    if (read_radiance_hdr_size(bytes.data(), bytes.size(), declared_width, declared_height))
        check_environment_size(file, declared_width, declared_height);
    Image image;
    uint32_t width = 0, height = 0;
    std::string error;
    if (!decode_radiance_hdr(bytes.data(), bytes.size(), width, height, image.rgb, error))
        throw IoError(file + ": not an OpenEXR or Radiance .hdr environment map (" + error + ")");
    image.width = int(width);
    image.height = int(height);
    return image;
}
}  // namespace

EnvironmentMap load_environment(const RenderSettings& settings) {
    const float rotation = settings.environment_rotation * 3.14159265358979f / 180.0f;
    if (settings.has_background) {
        EnvironmentMap env = make_constant_environment(
            glm::vec3(settings.background[0], settings.background[1], settings.background[2]));
        return env;
    }
    if (settings.environment_file.empty()) return {};
    const Image image = read_environment_image(settings.environment_file);
    try {
        EnvironmentMap env = make_environment_map(uint32_t(image.width), uint32_t(image.height), image.rgb,
                                                  settings.environment_intensity, rotation, settings.environment_file);
        if (env.clamped_texels > 0)
            std::fprintf(stderr, "fredholm: warning: %s: %zu texel(s) with negative values set to 0\n",
                         settings.environment_file.c_str(), env.clamped_texels);
        return env;
    } catch (const std::invalid_argument& e) {
        throw IoError(e.what());
    }
}

void check_render_fits(const PreparedScene& prepared, const RenderSettings& settings, const vk::Context& context,
                       const std::filesystem::path& file) {
    const RenderSettings s = with_device_defaults(settings, context, prepared.packed);
    const MemoryEstimate device = estimate_render_memory(prepared.packed, s);
    std::string problem = find_memory_problem(device, query_memory_limits(context));
    if (problem.empty())
        problem = find_memory_limit_problem(host_render_uses(prepared.scene, device), device, s.resolved_memory_limit(),
                                            is_cpu_device(context));
    if (!problem.empty())
        throw std::runtime_error(file.string() + ": " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                 " on " + context.device_name() + ": " + problem);
}

bool validation_requested_by_environment() {
    const char* value = std::getenv("FREDHOLM_VALIDATION");
    return value && std::strcmp(value, "0") != 0 && *value;
}

std::unique_ptr<vk::Context> make_compute_context(bool validation, const std::string& device_filter) {
    vk::ContextOptions options;
    options.validation = validation || validation_requested_by_environment();
    options.device_filter = device_filter;
    return std::make_unique<vk::Context>(options);
}

}  // namespace fh
