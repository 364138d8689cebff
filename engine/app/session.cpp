// Scene preparation with timings, and Vulkan context creation for the command-line tools.
#include "app/session.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "shared/layout.h"

namespace fh {
namespace {
constexpr uint32_t MAX_TRAVERSAL_DEPTH = 64;  // shaders/lib/traverse.glsl TRAVERSAL_STACK_SIZE

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

PreparedScene prepare_scene(const std::filesystem::path& file, const RenderSettings& settings) {
    PreparedScene prepared;
    auto start = std::chrono::steady_clock::now();
    LoadOptions load;
    load.rebase = (settings.disabled_techniques & gpu::TECHNIQUE_REBASE) == 0;
    prepared.scene = load_gltf(file, load);
    prepared.load_seconds = seconds_since(start);
    for (const std::string& warning : prepared.scene.warnings)
        std::fprintf(stderr, "fredholm: warning: %s\n", warning.c_str());

    BvhOptions bvh_options;
    bvh_options.max_leaf_size = settings.bvh_max_leaf_size;
    Bvh bvh = build_bvh(prepared.scene.positions, bvh_options);
    if (bvh.max_depth >= MAX_TRAVERSAL_DEPTH)
        throw SceneError(file.string() + ": BVH depth " + std::to_string(bvh.max_depth) +
                         " exceeds the traversal stack (" + std::to_string(MAX_TRAVERSAL_DEPTH) + ")");
    prepared.bvh_build_seconds = bvh.build_seconds;
    prepared.sah_cost = bvh.sah_cost;
    prepared.bvh_nodes = bvh.nodes.size();
    prepared.bvh_depth = bvh.max_depth;
    prepared.packed = pack_scene(prepared.scene, bvh);
    return prepared;
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
