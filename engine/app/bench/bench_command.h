// `fredholm bench`: renders a scene at several resolutions and prints samples/s, rays/s and stage times;
// with --techniques, also the render time with each robustness technique switched off; with --textures, the
// render time with the scene's textures (and other material effects) against factors only, and texture memory;
// with --effects, the scene compiled for its own effects against every effect compiled in.
#pragma once
#include <filesystem>

#include "render/settings.h"
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fh {

struct BenchCommand {
    std::filesystem::path scene;          // default: the shipped Cornell box
    std::vector<uint32_t> sizes{256, 512};
    uint32_t spp = 64;
    uint32_t max_depth = 10;
    Integrator integrator = Integrator::path;  // --integrator path|light|bdpt
    uint32_t repeats = 3;
    uint32_t bvh_leaf_size = 4;  // RenderSettings::bvh_max_leaf_size
    std::optional<bool> sort_rays;  // --sort-rays (also for --trace-rays); unset: auto (render/device_defaults.h)
    EffectBits disabled_effects = 0;  // --disable-effect: compiled out of every render and of --trace-rays
    bool compare_ray_order = false;  // --compare-ray-order: the render with the ray sort on against off
    bool compare_stores = false;     // --compare-stores: shade's uvec4 stores against field stores (--wide-stores)
    std::filesystem::path json;
    std::filesystem::path trace_rays;     // --trace-rays: time the extend stage alone over these rays
    std::filesystem::path hits_out;       // --hits-out: their hit distances (with --any-hit: 1 occluded, 0 not)
    bool any_hit = false;                 // --any-hit: the rays are shadow rays, traced by the connect stage
    std::string device;
    bool techniques = false;  // also time each robustness technique switched off (README cost table)
    bool textures = false;    // also time the scene with its material effects compiled out (factors only)
    bool effects = false;     // --effects: own effect set vs every material effect compiled in (time, build)
    bool instancing = false;  // --instancing: two-level BVH vs every instance copied (memory, build, render)
    bool motion = false;      // --motion: the --shutter's motion blur vs switched off vs no shutter
    RenderSettings pose;      // --time, --animation, --shutter (render_options.h add_animation_options)
    std::string environment_file;  // --env, --background: light for scenes without their own
    bool has_background = false;
    float background[3] = {1.0f, 1.0f, 1.0f};
};

void add_bench_options(CLI::App& app, BenchCommand& command);
int run_bench(const BenchCommand& command);

}  // namespace fh
