// Benchmark: median of N renders per resolution, timing only the render (not loading, BVH or pipelines).
#include "app/bench_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/session.h"
#include "io/atomic_write.h"
#include "io/image.h"
#include "render/camera_setup.h"
#include "render/renderer.h"

namespace fh {
namespace {

#ifndef FREDHOLM_DEFAULT_SCENE
#define FREDHOLM_DEFAULT_SCENE "scenes/cornell.gltf"
#endif

template <typename T>
T median(std::vector<T> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

}  // namespace

void add_bench_options(CLI::App& app, BenchCommand& c) {
    app.add_option("scene", c.scene, "glTF scene (default: the shipped Cornell box)");
    app.add_option("--sizes", c.sizes, "square image sizes to time")->check(CLI::Range(16u, 8192u));
    app.add_option("--spp", c.spp, "samples per pixel")->check(CLI::Range(1u, 1u << 16));
    app.add_option("--max-depth", c.max_depth, "path length in segments (0 = unlimited)");
    app.add_option("--repeats", c.repeats, "renders per size; the median is reported")->check(CLI::Range(1u, 100u));
    app.add_option("--json", c.json, "also write the figures as JSON");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
}

int run_bench(const BenchCommand& c) {
    std::filesystem::path scene_file = c.scene.empty() ? std::filesystem::path(FREDHOLM_DEFAULT_SCENE) : c.scene;
    PreparedScene prepared = prepare_scene(scene_file);
    auto context = make_compute_context(false, c.device);
    SceneCamera camera = choose_camera(prepared.scene, -1);
    std::printf("scene %s: %zu triangles, BVH %zu nodes built in %.3f s (SAH cost %.2f)\n",
                scene_file.string().c_str(), prepared.scene.triangle_count(), prepared.bvh_nodes,
                prepared.bvh_build_seconds, prepared.sah_cost);
    std::printf("device %s; %u spp, max depth %u, median of %u\n\n", context->device_name().c_str(), c.spp,
                c.max_depth, c.repeats);
    std::printf("%-9s %10s %12s %12s   %s\n", "size", "seconds", "Msamples/s", "Mrays/s", "stage seconds (GPU timestamps)");

    nlohmann::json results = nlohmann::json::array();
    for (uint32_t size : c.sizes) {
        RenderSettings settings;
        settings.width = settings.height = size;
        settings.spp = c.spp;
        settings.max_depth = c.max_depth;
        Renderer renderer(*context, prepared.packed, camera, settings, prepared.scene.bounds_min,
                          prepared.scene.bounds_max);
        std::vector<RenderStats> runs;
        for (uint32_t r = 0; r < c.repeats; ++r) runs.push_back(renderer.render());
        std::sort(runs.begin(), runs.end(),
                  [](const RenderStats& a, const RenderStats& b) { return a.render_seconds < b.render_seconds; });
        const RenderStats& m = runs[runs.size() / 2];
        double samples = double(size) * size * m.spp_done;
        double rays = double(m.traced_rays + m.traced_shadow_rays);
        std::string stages;
        for (const auto& [name, seconds] : m.stage_seconds) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%s %.3f  ", name.c_str(), seconds);
            stages += buf;
        }
        std::printf("%4ux%-4u %10.3f %12.3f %12.3f   %s\n", size, size, m.render_seconds,
                    samples / m.render_seconds * 1e-6, rays / m.render_seconds * 1e-6, stages.c_str());
        results.push_back({{"width", size},
                           {"height", size},
                           {"spp", m.spp_done},
                           {"render_seconds", m.render_seconds},
                           {"samples_per_second", samples / m.render_seconds},
                           {"rays_per_second", rays / m.render_seconds},
                           {"stage_seconds", m.stage_seconds},
                           {"nonfinite_samples", m.nonfinite_samples}});
    }
    if (!c.json.empty()) {
        nlohmann::json j{{"scene", scene_file.string()}, {"device", context->device_name()}, {"max_depth", c.max_depth},
                         {"repeats", c.repeats}, {"results", results}};
        write_file_atomically(c.json, [&](const std::filesystem::path& temp) { std::ofstream(temp) << j.dump(2) << "\n"; });
    }
    return 0;
}

}  // namespace fh
