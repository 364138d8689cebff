// Runs a render end to end: validate outputs, load, build, render with progress, write atomically.
#include "app/cli/render_options.h"
#include "app/render/render_command.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "app/cli/interrupt.h"
#include "app/cli/integrator_choice.h"
#include "app/cli/progress.h"
#include "app/cli/resume.h"
#include "app/cli/session.h"
#include "vk/buffer.h"
#include "app/cli/setting_table.h"
#include "app/render/render_passes.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/camera/camera_setup.h"
#include "render/camera/lens.h"
#include "render/estimated_render.h"
#include "render/light_tracing.h"
#include "render/memory_estimate.h"
#include "render/techniques.h"
#include "render/device_defaults.h"

namespace fh {
namespace {

const char* VERSION = "fredholm 0.1.0";
constexpr uint32_t DEFAULT_MAX_SPP = 65536;  // --target-error without --max-spp

// The settings that decide every sample's value (what a resume must match), plus the samples done.
ImageMetadata make_metadata(const RenderCommand& c, const std::string& scene_hash, uint32_t spp_done, EffectBits effects) {
    const RenderSettings& s = c.settings;
    ImageMetadata metadata{
        {"fredholm:renderer", VERSION},
        {"fredholm:scene", c.scene.filename().string()},
        {"fredholm:scene_hash", scene_hash},
        {"fredholm:image_size", std::to_string(s.width) + "x" + std::to_string(s.height)},
        {"fredholm:crop", describe_crop(s.crop_x0, s.crop_y0, s.crop_x1, s.crop_y1)},
        {"fredholm:first_sample", std::to_string(c.first_sample)},
        {"fredholm:spp", std::to_string(spp_done)},
        {"fredholm:effects", describe_effects(select_effects(effects, s.forced_effects, s.disabled_effects))},
        {"fredholm:colorspace", "scene-linear Rec.709"}};
    for (const SettingInfo& e : setting_table())
        if (e.metadata_key) metadata.emplace(e.metadata_key, e.describe(s));
    if (connects_subpaths(s.integrator)) metadata.emplace("fredholm:bdpt_depth", std::to_string(bdpt_depth(s)));
    if (s.integrator == Integrator::vcm)
        metadata.emplace("fredholm:estimator", "consistent, not unbiased (vertex merging: its bias falls as the merging "
                                               "radius shrinks with the samples)");
    return metadata;
}

// Once per render, where --max-depth does not say it: how long the paths are that every BDPT strategy makes.
void print_bdpt_depth(const RenderSettings& s) {
    if (s.max_depth != 0 && s.max_depth <= BDPT_MAX_DEPTH) return;
    std::fprintf(stderr,
                 "fredholm: %s: every strategy makes paths of up to %u segments (%s; --max-depth 1 to %u sets it), "
                 "longer ones%s are made by next-event estimation and light hits alone\n",
                 to_string(s.integrator), bdpt_depth(s), s.max_depth == 0 ? "the default" : "the most it stores", BDPT_MAX_DEPTH,
                 s.max_depth == 0 ? "" : (" up to " + std::to_string(s.max_depth)).c_str());
}

void write_stats(const std::filesystem::path& file, const RenderCommand& c, const PreparedScene& prepared,
                 const SceneCamera& camera, const RenderOutcome& outcome, uint32_t first_sample, const std::string& device,
                 const CameraMedia& camera_media) {
    const RenderSettings& s = c.settings;
    const RenderStats& stats = outcome.stats;
    const double samples = double(outcome.samples);
    double rays = double(stats.traced_rays + stats.traced_shadow_rays);
    nlohmann::json j;
    j["scene"] = c.scene.string();
    j["device"] = device;
    j["width"] = s.width;
    j["height"] = s.height;
    j["spp"] = stats.spp_done;
    j["first_sample"] = first_sample;  // where this run started (resumed or --samples); rates count its samples only
    j["crop"] = describe_crop(s.crop_x0, s.crop_y0, s.crop_x1, s.crop_y1);
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
    j["bvh_wide_sah_cost"] = prepared.wide_sah_cost;
    j["triangles"] = prepared.scene.rendered_triangle_count();  // rendered (every instance)
    j["triangles_stored"] = prepared.scene.triangle_count();    // in device memory (instanced meshes once)
    j["instances"] = prepared.scene.instances.size();
    j["triangles_unique"] = prepared.scene.unique_triangle_count;
    j["emitters"] = prepared.packed.emitters.size();
    j["punctual_lights"] = prepared.packed.punctual_lights.size();
    j["light_sampler"] = prepared.packed.light_sampler;  // as chosen (--light-sampler auto resolved)
    j["light_tree_lights"] = prepared.packed.light_tree_lights;
    j["light_tree_depth"] = prepared.packed.light_tree_depth;
    j["light_tree_build_seconds"] = prepared.packed.light_tree_build_seconds;
    j["effects"] = describe_effects(select_effects(prepared.packed.effects.bits, s.forced_effects, s.disabled_effects));
    // The volumes the camera stands in (glTF material indices, innermost first), where its paths start.
    std::string media;
    for (uint32_t m : camera_media)
        if (m != gpu::INVALID_INDEX) media += (media.empty() ? "material " : " in material ") + std::to_string(m);
    j["camera_medium"] = media.empty() ? std::string("none") : media;
    j["animations"] = prepared.scene.animations;
    j["moving_instances"] = prepared.scene.moving_instances;
    j["motion_segments"] = prepared.scene.motion_segments;  // keys of moving instances: this + 1
    if (s.animate || s.has_shutter()) {
        j["animation"] = prepared.scene.animation;
        j["time"] = s.time;
        j["animation_start"] = prepared.scene.animation_start;
        j["animation_end"] = prepared.scene.animation_end;
    }
    if (camera.has_lens()) {  // as resolved: the f-number's radius, the distance --focus-on or the centre found
        j["aperture_radius"] = camera.aperture_radius;
        j["focus_distance"] = camera.focus_distance;
    }
    j["variants"] = prepared.scene.variants;
    j["textures"] = prepared.packed.texture_images.size();
    j["texels"] = prepared.packed.texels.size();
    j["texture_bytes"] = prepared.packed.texels.size() * 4;
    j["render_origin"] = {prepared.scene.origin.x, prepared.scene.origin.y, prepared.scene.origin.z};
    j["stage_seconds"] = stats.stage_seconds;
    // Memory held as the image is written (the renderer still alive): what the soak tests (tests/soak/) follow.
    const vk::DeviceMemoryInUse device_memory = vk::device_memory_in_use();
    j["device_memory_bytes"] = device_memory.bytes;
    j["device_allocations"] = device_memory.allocations;
    j["host_resident_bytes"] = resident_memory_bytes();
    // The image's estimated relative error (error_estimate.h); null where it has none.
    j["relative_error"] = outcome.estimate && std::isfinite(outcome.error) ? nlohmann::json(outcome.error)
                                                                            : nlohmann::json(nullptr);
    j.update(outcome.stats_json);
    for (const SettingInfo& e : setting_table())  // the settings as asked for
        if (e.stats_key) j[e.stats_key] = e.stats ? e.stats(s) : nlohmann::json(e.describe(s));
    write_file_atomically(file, [&](const std::filesystem::path& temp) {
        std::ofstream out(temp);
        out << j.dump(2) << "\n";
        if (!out) throw IoError(temp.string() + ": cannot write statistics");
    });
}

// "; relative error 1.23%" (or "not estimated yet" below two complete batches).
std::string describe_error(double error) {
    if (!std::isfinite(error)) return "; relative error not estimated (fewer than 2 batches of samples)";
    char text[96];
    std::snprintf(text, sizeof text, "; estimated relative error %.3g%%", 100.0 * error);
    return text;
}

void parse_sample_range(const std::string& text, uint32_t& first, uint32_t& end) {
    unsigned long a = 0, b = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%lu:%lu%c", &a, &b, &tail) != 2 || text.find('-') != std::string::npos)
        throw CLI::ValidationError("--samples", "'" + text + "' is not A:B (sample indices, B exclusive)");
    if (a >= b || b > (1ul << 24))
        throw CLI::ValidationError("--samples", "'" + text + "' needs 0 <= A < B <= 16777216");
    first = uint32_t(a);
    end = uint32_t(b);
}

// --crop against the image size: one usage error naming what is wrong.
void apply_crop(const std::string& text, RenderSettings& s) {
    if (text.empty()) return;
    unsigned x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%u,%u,%u,%u%c", &x0, &y0, &x1, &y1, &tail) != 4 ||
        text.find('-') != std::string::npos)
        throw CLI::ValidationError("--crop", "'" + text + "' is not X0,Y0,X1,Y1 (pixels, X1 and Y1 exclusive)");
    if (x0 >= x1 || y0 >= y1 || x1 > s.width || y1 > s.height)
        throw CLI::ValidationError("--crop", "'" + text + "' is not a non-empty region inside the " +
                                                 std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
    s.crop_x0 = x0, s.crop_y0 = y0, s.crop_x1 = x1, s.crop_y1 = y1;
}

}  // namespace

void add_render_options(CLI::App& app, RenderCommand& c) {
    add_camera_pose_options(app, c.pose);
    RenderSettings& s = c.settings;
    app.add_option("scene", c.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
    app.add_option("-o,--output", c.output, "output OpenEXR image (scene-linear Rec.709, float32)")->required();
    app.add_option("--width", s.width, "image width in pixels")->check(CLI::Range(1u, 16384u));
    app.add_option("--height", s.height, "image height in pixels")->check(CLI::Range(1u, 16384u));
    auto* spp = app.add_option("--spp", s.spp, "samples per pixel")->check(CLI::Range(1u, 1u << 24));
    app.add_option_function<std::string>(
           "--samples",
           [&c](const std::string& text) {
               parse_sample_range(text, c.first_sample, c.settings.spp);
               c.sample_range = true;
           },
           "render only sample indices A..B-1 of every pixel (A:B), a part for fredholm merge (replaces --spp)")
        ->excludes(spp);
    app.add_option("--target-error", c.target_error,
                   "render until the image's estimated relative error (relative RMSE of luminance) is at most this, "
                   "e.g. 0.01; up to --max-spp")
        ->check(CLI::Range(1e-6, 10.0))
        ->excludes(spp);
    app.add_option("--max-spp", c.max_spp, "with --target-error: stop at this many samples per pixel (default 65536)")
        ->check(CLI::Range(1u, 1u << 24))
        ->excludes(spp);
    app.add_option("--max-seconds", c.max_seconds, "stop after this many seconds of rendering (at a sample index)")
        ->check(CLI::Range(1e-3, 1e9));
    app.add_flag("--adaptive", c.adaptive,
                 "spend samples where the noise is: a pilot of a few spp with its own seed measures each pixel, then "
                 "each 4x4 tile gets its own count, in the time of a uniform --spp render (or, with --target-error, "
                 "the least time predicted to reach it); unbiased, path tracing only");
    app.add_option("--crop", c.crop, "render only pixels X0..X1-1 by Y0..Y1-1 (X0,Y0,X1,Y1) of the image, a part for "
                                     "fredholm merge");
    add_setting_options(app, s, {"max-depth", "seed", "camera"});
    app.add_option("--png", c.png, "also write a tone-mapped sRGB PNG preview");
    add_tone_options(app, c.exposure_ev, c.tone_curve, "PNG");
    app.add_option("--stats", c.stats, "write render statistics as JSON");
    app.add_option_function<std::string>(
        "--aov",
        [&c](const std::string& list) {
            try {
                c.aovs = parse_aovs(list);
            } catch (const std::invalid_argument& e) {
                throw CLI::ValidationError("--aov", e.what());
            }
            c.aov_list = list;
            c.settings.aovs = c.aovs.any_recorded();
        },
        "extra EXR layers: albedo, normal (the first non-specular hit's, for denoisers), depth (distance to the first "
        "hit), spp, variance (always written), comma-separated");
    add_sampling_options(app, s);
    app.add_option_function<std::string>(
        "--bdpt-strategy",
        [&s](const std::string& text) {
            unsigned a = 0, b = 0;
            char extra = 0;
            if (std::sscanf(text.c_str(), "%u,%u%c", &a, &b, &extra) != 2 || b < 1 || a > 1000 || b > 1000)
                throw CLI::ValidationError("--bdpt-strategy", "'" + text + "' is not S,T (light and camera vertices, T >= 1)");
            s.bdpt_strategy_s = a;
            s.bdpt_strategy_t = b;
        },
        "with --integrator bdpt: only the strategy with S light and T camera vertices, unweighted (a check of one "
        "strategy)");
    add_robustness_options(app, s);
    add_environment_options(app, s);
    add_lens_options(app, s);
    add_animation_options(app, s);
    auto* frames = app.add_option("--frames", c.frames,
                                  "render frames A:B of the animation, frame f at time f / --fps; -o, --png and --stats "
                                  "need a run of # for the frame number (out_####.exr)");
    app.add_option("--fps", c.fps, "frames per second of --frames (default 24)")->check(CLI::Range(1e-3, 1e6));
    app.add_flag("--validate", c.validation, "enable Vulkan validation layers (also FREDHOLM_VALIDATION=1)");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
    app.add_flag("-q,--quiet", c.quiet, "no summary line");
    // "--resume" alone continues the output file itself; "--resume FILE" continues FILE into the output.
    app.add_option_function<std::string>(
           "--resume", [&c](const std::string& file) {
               c.resume = true;
               c.resume_file = file;
           },
           "continue a render written by fredholm render (default: the -o file) up to --spp samples")
        ->expected(0, 1)
        ->excludes(frames);
}

namespace {

struct FrameRange {
    long first = 0, last = 0;
};

FrameRange parse_frames(const std::string& text) {
    FrameRange r;
    const size_t colon = text.find(':');
    try {
        size_t used_a = 0, used_b = 0;
        r.first = std::stol(text.substr(0, colon), &used_a);
        r.last = colon == std::string::npos ? r.first : std::stol(text.substr(colon + 1), &used_b);
        if (used_a != (colon == std::string::npos ? text.size() : colon) ||
            (colon != std::string::npos && used_b != text.size() - colon - 1))
            throw std::invalid_argument(text);
    } catch (const std::exception&) {
        throw CLI::ValidationError("--frames", "'" + text + "' is not A:B (frame numbers)");
    }
    if (r.first < 0 || r.last < r.first || r.last > 10000000)
        throw CLI::ValidationError("--frames", "'" + text + "' needs 0 <= A <= B <= 10000000");
    return r;
}

// The file of frame `frame`: the last run of '#' in the file name replaced by the number, zero-padded to its length.
std::filesystem::path frame_file(const std::filesystem::path& pattern, long frame, const char* option) {
    std::string name = pattern.filename().string();
    const size_t end = name.find_last_of('#');
    if (end == std::string::npos)
        throw CLI::ValidationError(option, pattern.string() + " has no # for the frame number (e.g. out_####.exr)");
    size_t begin = end;
    while (begin > 0 && name[begin - 1] == '#') --begin;
    std::string number = std::to_string(frame);
    if (number.size() < end + 1 - begin) number.insert(0, end + 1 - begin - number.size(), '0');
    name.replace(begin, end + 1 - begin, number);
    return pattern.parent_path() / name;
}

// One image; `shared_context`: the Vulkan device a sequence keeps for all its frames (null: its own).
int run_frame(const RenderCommand& c, vk::Context* shared_context = nullptr);

}  // namespace

int run_render(const RenderCommand& c) {
    if (c.frames.empty()) return run_frame(c);
    const FrameRange range = parse_frames(c.frames);
    // Every output name is checked before the first frame renders.
    for (long f : {range.first, range.last}) {
        check_writable(frame_file(c.output, f, "-o"));
        if (!c.png.empty()) check_writable(frame_file(c.png, f, "--png"));
        if (!c.stats.empty()) check_writable(frame_file(c.stats, f, "--stats"));
    }
    const auto start = std::chrono::steady_clock::now();
    const auto context = make_compute_context(c.validation, c.device);  // one device for every frame
    for (long f = range.first; f <= range.last; ++f) {
        RenderCommand frame = c;
        frame.frames.clear();
        frame.settings.animate = true;
        frame.settings.time = double(f) / c.fps;
        frame.output = frame_file(c.output, f, "-o");
        if (!c.png.empty()) frame.png = frame_file(c.png, f, "--png");
        if (!c.stats.empty()) frame.stats = frame_file(c.stats, f, "--stats");
        const int rc = run_frame(frame, context.get());
        if (rc != 0) return rc;
        if (!c.quiet)
            std::fprintf(stderr, "fredholm: frame %ld (%ld of %ld, t = %.6g s) done, %.1f s elapsed\n", f, f - range.first + 1,
                         range.last - range.first + 1, frame.settings.time,
                         seconds_since(start));
        if (interrupt_requested()) return 130;
    }
    return 0;
}

namespace {

int run_frame(const RenderCommand& command, vk::Context* shared_context) {
    RenderCommand c = command;
    apply_crop(c.crop, c.settings);
    // Without roulette and without a depth limit a path in a closed scene never ends.
    if (!c.settings.russian_roulette && c.settings.max_depth == 0) {
        std::fprintf(stderr, "fredholm: usage error: --rr off needs a finite --max-depth (paths that never escape "
                             "would never end)\n");
        return 2;
    }
    // A pilot could choose differently for another part of the same image.
    if (c.settings.integrator == Integrator::automatic && (c.resume || c.first_sample != 0 || c.settings.has_crop())) {
        std::fprintf(stderr, "fredholm: usage error: --integrator auto cannot continue or split a render (--resume, "
                             "--samples, --crop): name the integrator for every part\n");
        return 2;
    }
    if (c.settings.integrator == Integrator::automatic && c.settings.bdpt_strategy_t != 0) {
        std::fprintf(stderr, "fredholm: usage error: --bdpt-strategy needs --integrator bdpt, not auto\n");
        return 2;
    }
    if (c.max_spp != 0 && c.target_error == 0) {
        std::fprintf(stderr, "fredholm: usage error: --max-spp is the sample limit of --target-error; without a "
                             "target give --spp\n");
        return 2;
    }
    if (c.target_error > 0 && c.first_sample != 0) {
        std::fprintf(stderr, "fredholm: usage error: --target-error renders the whole sample range (not --samples)\n");
        return 2;
    }
    if (c.adaptive && (c.resume || c.sample_range)) {
        std::fprintf(stderr, "fredholm: usage error: --adaptive renders a whole image afresh (not --resume or "
                             "--samples): its pixels hold different numbers of samples\n");
        return 2;
    }
    if (c.adaptive && c.settings.integrator != Integrator::path) {
        std::fprintf(stderr, "fredholm: usage error: --adaptive needs --integrator path (light subpaths land on "
                             "every pixel, whatever samples it was given)\n");
        return 2;
    }
    if (c.adaptive && c.target_error == 0 && c.settings.spp < 8) {
        std::fprintf(stderr, "fredholm: usage error: --adaptive needs --spp 8 or more (a pilot of 4 spp comes first)\n");
        return 2;
    }
    c.settings.adaptive = c.adaptive;
    if (c.target_error > 0) c.settings.spp = c.max_spp != 0 ? c.max_spp : DEFAULT_MAX_SPP;
    if (c.settings.aovs && c.settings.integrator == Integrator::light) {
        std::fprintf(stderr, "fredholm: usage error: --aov albedo, normal and depth come from camera paths, which "
                             "--integrator light does not trace\n");
        return 2;
    }
    // Fail before any work if an output cannot be written or the render to continue does not match.
    check_writable(c.output);
    if (!c.png.empty()) check_writable(c.png);
    if (!c.stats.empty()) check_writable(c.stats);
    const RenderSettings& settings = c.settings;
    const std::string scene_hash = hash_file(c.scene);
    FilmFile saved;
    saved.first_sample = saved.end_sample = c.first_sample;
    if (c.resume) {
        const std::filesystem::path& file = c.resume_file.empty() ? c.output : c.resume_file;
        saved = read_saved_film(file, make_metadata(c, scene_hash, 0, 0));
        if (saved.has_aov_sums != settings.aovs)
            throw std::runtime_error(file.string() + ": cannot resume: it was rendered " +
                                     (saved.has_aov_sums ? "with" : "without") + " --aov albedo, normal or depth, "
                                     "this render " + (settings.aovs ? "with" : "without") + " (give the same --aov)");
        if (saved.end_sample > settings.spp)
            throw std::runtime_error(file.string() + ": cannot resume: it already has " +
                                     std::to_string(saved.end_sample) + " spp, more than --spp " +
                                     std::to_string(settings.spp));
    }
    // From here on Ctrl-C and SIGTERM finish the sample index in progress, then write what they have.
    install_interrupt_handlers();

    PreparedScene prepared = prepare_scene(c.scene, settings);
    std::unique_ptr<vk::Context> owned;
    if (!shared_context) owned = make_compute_context(c.validation, c.device);
    vk::Context* context = shared_context ? shared_context : owned.get();
    const SceneCamera camera = apply_lens(*context, prepared.packed,
                                          apply_camera_pose(choose_camera(prepared.scene, settings.camera), c.pose),
                                          settings);
    if (c.settings.integrator == Integrator::automatic) {
        const IntegratorChoice choice = choose_integrator_by_pilot(*context, prepared.packed, camera, c.settings);
        if (!c.quiet) std::fprintf(stderr, "fredholm: %s\n", choice.report.c_str());
        c.settings.integrator = choice.integrator;
        apply_light_sampler(prepared, c.scene, c.settings);
    }
    if (connects_subpaths(settings.integrator) && !c.quiet) print_bdpt_depth(settings);
    c.settings = with_device_defaults(c.settings, *context, prepared.packed);
    check_render_fits(prepared, settings, *context, c.scene);
    Renderer renderer(*context, prepared.packed, camera, settings);
    if (!c.resume) renderer.clear_film();
    else renderer.write_film_state(saved.film);
    if (c.resume && settings.aovs) renderer.write_aov_film(saved.aov_sums);

    const bool old_film = c.resume && !saved.has_batches;  // saved before error batches existed: no estimate
    if (old_film && c.target_error > 0)
        throw std::runtime_error((c.resume_file.empty() ? c.output : c.resume_file).string() +
                                 ": cannot resume to a target error: it was written without error batches");
    if (old_film && !c.quiet)
        std::fprintf(stderr, "fredholm: note: the film to continue has no error batches (written by an older "
                             "fredholm), so this render has no error estimate\n");
    // Stop only once a wave has finished a sample index for every pixel (the film then holds samples
    // [0, spp_done) everywhere, so it can be resumed exactly); waves that cover part of the pixels continue.
    ProgressLine progress;
    const auto show_progress = [&](const EstimatedRenderStatus& status) {
        if (c.target_error > 0 && !c.adaptive) progress.update_target(status.spp_done, status.error, c.target_error);
        else progress.update(status.spp_done, status.spp_total);
        return !interrupt_requested();
    };
    RenderOutcome outcome = c.adaptive ? render_adaptive_pass(c, renderer, show_progress)
                                       : render_uniform(c, renderer, saved, c.resume, show_progress);
    progress.finish();
    const RenderStats& stats = outcome.stats;
    if (c.adaptive && !outcome.estimate) {  // interrupted before the image began
        std::fprintf(stderr, "fredholm: interrupted during the adaptive pilot: nothing written\n");
        return 130;
    }

    const Image image = renderer.read_film();
    ImageWindow window;
    if (settings.has_crop())
        window = {int(settings.crop_x0), int(settings.crop_y0), int(settings.width), int(settings.height)};
    ImageMetadata metadata = make_metadata(c, scene_hash, stats.spp_done, prepared.packed.effects.bits);
    metadata.insert(outcome.metadata.begin(), outcome.metadata.end());
    ExtraChannels channels = film_channels(renderer.read_film_state());
    channels.insert(outcome.channels.begin(), outcome.channels.end());
    FloatChannels& floats = outcome.floats;
    if (c.aovs.any_recorded() || c.aovs.spp) {
        const std::vector<gpu::AovPixel> sums = settings.aovs ? renderer.read_aov_film() : std::vector<gpu::AovPixel>{};
        const FloatChannels layers = aov_layers(c.aovs, sums, renderer.read_film_state());
        floats.insert(layers.begin(), layers.end());
        if (settings.aovs) {
            const ExtraChannels sum_channels = aov_sum_channels(sums);
            channels.insert(sum_channels.begin(), sum_channels.end());
        }
        metadata["fredholm:aovs"] = c.aov_list;
    }
    write_exr(c.output, image, metadata, channels, window, floats);
    if (!c.png.empty()) write_png(c.png, image, c.exposure_ev, c.tone_curve);
    if (!c.stats.empty()) write_stats(c.stats, c, prepared, camera, outcome, saved.end_sample, context->device_name(),
                                         renderer.camera_media());

    if (!c.quiet)
        std::fprintf(stderr, "fredholm: %s: %ux%u, %s in %.3f s (%.2f Msamples/s) on %s; %llu non-finite samples%s\n",
                     c.output.string().c_str(), settings.film_width(), settings.film_height(),
                     outcome.samples_text.c_str(), stats.render_seconds,
                     stats.render_seconds > 0 ? double(outcome.samples) / stats.render_seconds * 1e-6 : 0.0,
                     context->device_name().c_str(), (unsigned long long)stats.nonfinite_samples,
                     outcome.estimate ? describe_error(outcome.error).c_str() : "");
    if (!c.quiet && (c.target_error > 0 || c.max_seconds > 0) && outcome.stop != StopReason::interrupted)
        std::fprintf(stderr, "fredholm: stopped by %s%s\n", describe_stop(outcome.stop),
                     c.target_error > 0 && outcome.stop != StopReason::target ? " before the target error" : "");
    if (context->validation_message_count() > 0) {
        std::fprintf(stderr, "fredholm: error: %u Vulkan validation message(s)\n", context->validation_message_count());
        return 1;
    }
    if (interrupt_requested()) {
        std::fprintf(stderr, "fredholm: interrupted: wrote %s with %u spp (continue with --resume)\n",
                     c.output.string().c_str(), stats.spp_done);
        return 130;
    }
    return 0;
}

}  // namespace

}  // namespace fh
