// What every sub-command that renders needs: the scene loaded, its BVH built and packed, a Vulkan device.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "scene/bvh/bvh.h"
#include "scene/pack.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace fh {

struct PreparedScene {
    Scene scene;
    PackedScene packed;
    double load_seconds = 0;
    double bvh_build_seconds = 0;
    double sah_cost = 0;
    double wide_sah_cost = 0;
    size_t bvh_nodes = 0;
    uint32_t bvh_depth = 0;
};

// The BVH build's options for these settings (the leaf size).
BvhOptions make_bvh_options(const RenderSettings& settings);

// Loads and packs a scene (TECHNIQUE_REBASE and the BVH leaf size from `settings`); prints the loader's
// warnings to stderr.
PreparedScene prepare_scene(const std::filesystem::path& file, const RenderSettings& settings);

// The light sampler of settings.light_sampler for settings.integrator, set up in prepared.packed (scene/light/light_sampler.h;
// prepare_scene does it unless the integrator is still auto). Throws std::invalid_argument naming `file` for a tree
// with another integrator than path tracing.
void apply_light_sampler(PreparedScene& prepared, const std::filesystem::path& file, const RenderSettings& settings);

// Refuses a render whose buffers break the device's limits (render/memory_estimate.h find_memory_problem) or whose host
// and device memory break --memory-limit, before anything is allocated for it: std::runtime_error with one line naming
// `file`, the image size and the device. `settings`' wave size may still be unchosen (with_device_defaults is applied).
void check_render_fits(const PreparedScene& prepared, const RenderSettings& settings, const vk::Context& context,
                       const std::filesystem::path& file);

// The environment light the settings ask for (--env, --background), or an empty map. Throws IoError naming
// the file for an unreadable or invalid map.
EnvironmentMap load_environment(const RenderSettings& settings);

// A Vulkan context for compute; validation when asked or when FREDHOLM_VALIDATION=1.
std::unique_ptr<vk::Context> make_compute_context(bool validation, const std::string& device_filter);
bool validation_requested_by_environment();

}  // namespace fh
