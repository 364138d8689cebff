// Runs a render end to end: validate outputs, load, build, render with progress, write atomically.
#include "app/render_command.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "app/interrupt.h"
#include "app/progress.h"
#include "app/session.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/camera_setup.h"

namespace fh {
namespace {

const char* VERSION = "fredholm 0.1.0";

ImageMetadata make_metadata(const RenderCommand& c, const RenderStats& stats) {
    const RenderSettings& s = c.settings;
    return {{"fredholm:renderer", VERSION},
            {"fredholm:scene", c.scene.filename().string()},
            {"fredholm:spp", std::to_string(stats.spp_done)},
            {"fredholm:seed", std::to_string(s.seed)},
            {"fredholm:max_depth", std::to_string(s.max_depth)},
            {"fredholm:camera", std::to_string(s.camera)},
            {"fredholm:filter", to_string(s.filter)},
            {"fredholm:nee", s.nee ? "on" : "off"},
            {"fredholm:mis", s.mis ? "on" : "off"},
            {"fredholm:rr", s.russian_roulette ? "on" : "off"},
            {"fredholm:colorspace", "scene-linear Rec.709"}};
}

void write_stats(const std::filesystem::path& file, const RenderCommand& c, const PreparedScene& prepared,
                 const RenderStats& stats, const std::string& device) {
    const RenderSettings& s = c.settings;
    double samples = double(s.width) * s.height * stats.spp_done;
    double rays = double(stats.traced_rays + stats.traced_shadow_rays);
    nlohmann::json j;
    j["scene"] = c.scene.string();
    j["device"] = device;
    j["width"] = s.width;
    j["height"] = s.height;
    j["spp"] = stats.spp_done;
    j["seed"] = s.seed;
    j["max_depth"] = s.max_depth;
    j["render_seconds"] = stats.render_seconds;
    j["samples_per_second"] = stats.render_seconds > 0 ? samples / stats.render_seconds : 0.0;
    j["rays_per_second"] = stats.render_seconds > 0 ? rays / stats.render_seconds : 0.0;
    j["traced_rays"] = stats.traced_rays;
    j["traced_shadow_rays"] = stats.traced_shadow_rays;
    j["nonfinite_samples"] = stats.nonfinite_samples;
    j["escaped_rays"] = stats.escaped_rays;
    j["load_seconds"] = prepared.load_seconds;
    j["bvh_build_seconds"] = prepared.bvh_build_seconds;
    j["bvh_nodes"] = prepared.bvh_nodes;
    j["bvh_depth"] = prepared.bvh_depth;
    j["bvh_sah_cost"] = prepared.sah_cost;
    j["triangles"] = prepared.scene.triangle_count();
    j["emitters"] = prepared.packed.emitters.size();
    j["stage_seconds"] = stats.stage_seconds;
    write_file_atomically(file, [&](const std::filesystem::path& temp) {
        std::ofstream out(temp);
        out << j.dump(2) << "\n";
        if (!out) throw IoError(temp.string() + ": cannot write statistics");
    });
}

}  // namespace

void add_render_options(CLI::App& app, RenderCommand& c) {
    RenderSettings& s = c.settings;
    app.add_option("scene", c.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
    app.add_option("-o,--output", c.output, "output OpenEXR image (scene-linear Rec.709, float32)")->required();
    app.add_option("--width", s.width, "image width in pixels")->check(CLI::Range(1u, 16384u));
    app.add_option("--height", s.height, "image height in pixels")->check(CLI::Range(1u, 16384u));
    app.add_option("--spp", s.spp, "samples per pixel")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--max-depth", s.max_depth, "longest path in segments after the camera (0 = unlimited)")
        ->check(CLI::Range(0u, 100000u));
    app.add_option("--seed", s.seed, "random seed");
    app.add_option("--camera", s.camera, "glTF camera index (default: first camera, or a framing camera)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--png", c.png, "also write a tone-mapped sRGB PNG preview");
    app.add_option("--exposure", c.exposure_ev, "PNG exposure in stops");
    std::map<std::string, ToneCurve> curves{{"aces", ToneCurve::aces}, {"clamp", ToneCurve::clamp}};
    app.add_option("--tonemap", c.tone_curve, "PNG tone curve: aces (Narkowicz ACES fit) or clamp")
        ->transform(CLI::CheckedTransformer(curves, CLI::ignore_case));
    app.add_option("--stats", c.stats, "write render statistics as JSON");
    std::map<std::string, PixelFilter> filters{{"box", PixelFilter::box}, {"gaussian", PixelFilter::gaussian}};
    app.add_option("--filter", s.filter, "pixel filter: box (1 pixel) or gaussian (importance sampled)")
        ->transform(CLI::CheckedTransformer(filters, CLI::ignore_case));
    app.add_option("--filter-radius", s.filter_radius, "Gaussian truncation radius in pixels")
        ->check(CLI::Range(0.5f, 8.0f));
    std::map<std::string, bool> on_off{{"on", true}, {"off", false}};
    app.add_option("--nee", s.nee, "next-event estimation: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--mis", s.mis, "multiple importance sampling: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--rr", s.russian_roulette, "Russian roulette: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--wave-paths", s.wave_paths, "paths in flight per wave")->check(CLI::Range(1024u, 1u << 22));
    app.add_flag("--validate", c.validation, "enable Vulkan validation layers (also FREDHOLM_VALIDATION=1)");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
    app.add_flag("-q,--quiet", c.quiet, "no summary line");
}

int run_render(const RenderCommand& c) {
    // Fail before any work if an output cannot be written.
    check_writable(c.output);
    if (!c.png.empty()) check_writable(c.png);
    if (!c.stats.empty()) check_writable(c.stats);

    PreparedScene prepared = prepare_scene(c.scene);
    SceneCamera camera = choose_camera(prepared.scene, c.settings.camera);
    auto context = make_compute_context(c.validation, c.device);
    Renderer renderer(*context, prepared.packed, camera, c.settings, prepared.scene.bounds_min,
                      prepared.scene.bounds_max);

    install_interrupt_handlers();
    ProgressLine progress;
    RenderStats stats = renderer.render([&](uint32_t done, uint32_t total) {
        progress.update(done, total);
        return !interrupt_requested();
    });
    progress.finish();

    Image image = renderer.read_film();
    write_exr(c.output, image, make_metadata(c, stats));
    if (!c.png.empty()) write_png(c.png, image, c.exposure_ev, c.tone_curve);
    if (!c.stats.empty()) write_stats(c.stats, c, prepared, stats, context->device_name());

    if (!c.quiet)
        std::fprintf(stderr, "fredholm: %s: %ux%u, %u spp in %.3f s (%.2f Msamples/s) on %s; %llu non-finite samples\n",
                     c.output.string().c_str(), c.settings.width, c.settings.height, stats.spp_done,
                     stats.render_seconds,
                     double(c.settings.width) * c.settings.height * stats.spp_done / stats.render_seconds * 1e-6,
                     context->device_name().c_str(), (unsigned long long)stats.nonfinite_samples);
    if (context->validation_message_count() > 0) {
        std::fprintf(stderr, "fredholm: error: %u Vulkan validation message(s)\n", context->validation_message_count());
        return 1;
    }
    if (interrupt_requested()) {
        std::fprintf(stderr, "fredholm: interrupted: wrote %s with %u spp\n", c.output.string().c_str(), stats.spp_done);
        return 130;
    }
    return 0;
}

}  // namespace fh
