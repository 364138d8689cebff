// The viewer's frame loop: input -> (restart or rebuild) -> a bounded slice of samples -> present -> title.
#include "app/view/viewer_command.h"

#include "app/cli/progress.h"
#include "app/cli/render_options.h"
#include "app/cli/setting_table.h"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "app/cli/session.h"
#include "app/view/viewer_controls.h"
#include "app/view/viewer_present.h"
#include "app/view/viewer_window.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/camera/camera_setup.h"
#include "render/camera/lens.h"
#include "render/estimated_render.h"
#include "render/renderer.h"
#include "scene/memory_limit.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/swapchain.h"

namespace fh {
namespace {

using Clock = std::chrono::steady_clock;


std::unique_ptr<vk::Context> make_present_context(const ViewCommand& c) {
    vk::ContextOptions options;
    options.validation = c.validation || validation_requested_by_environment();
    options.device_filter = c.device;
    options.instance_extensions = ViewerWindow::required_instance_extensions();
    options.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    try {
        return std::make_unique<vk::Context>(options);
    } catch (const vk::VulkanError& e) {
        if (e.result == VK_ERROR_EXTENSION_NOT_PRESENT)
            throw DisplayUnavailable("the Vulkan driver or device cannot present to a window (" + std::string(e.what()) +
                                     "); use `fredholm render`");
        throw;
    }
}

// The scripted actions of a --frames run (tests): resize, orbit, pan, zoom, depth, nee, tonemap,
// print, reset.
std::vector<std::string> split_script(const std::string& script) {
    std::vector<std::string> actions;
    std::stringstream in(script);
    for (std::string action; std::getline(in, action, ',');)
        if (!action.empty()) actions.push_back(action);
    return actions;
}

// Resizes the window, to a smaller one and back on alternate calls (so that a long run returns to its first size),
// and waits (up to 2 s) for the new framebuffer size to arrive.
void scripted_resize(ViewerWindow& window) {
    static bool shrunk = false;
    VkExtent2D before = window.framebuffer_size();
    if (!shrunk) window.set_size(before.width * 3 / 4 + 8, before.height + 24);
    else window.set_size((before.width - 8) * 4 / 3, before.height - 24);
    shrunk = !shrunk;
    for (auto start = Clock::now(); seconds_since(start) < 2.0;) {
        window.poll();
        VkExtent2D now = window.framebuffer_size();
        if (now.width != before.width || now.height != before.height) return;
    }
    throw std::runtime_error("--script resize: the window did not change size within 2 s");
}

void run_script_action(const std::string& action, ViewerWindow& window, WindowInput& input) {
    if (action == "resize") scripted_resize(window);
    else if (action == "orbit") { input.orbit_dx += 60; input.orbit_dy += 25; }
    else if (action == "pan") { input.pan_dx += 10; input.pan_dy -= 6; }
    else if (action == "zoom") input.wheel += 2;
    else if (action == "depth") input.pressed.push_back(GLFW_KEY_LEFT_BRACKET);
    else if (action == "nee") input.pressed.push_back(GLFW_KEY_N);
    else if (action == "tonemap") input.pressed.push_back(GLFW_KEY_T);
    else if (action == "print") input.pressed.push_back(GLFW_KEY_C);
    else if (action == "reset") input.pressed.push_back(GLFW_KEY_R);
    else if (action == "aperture") input.pressed.push_back(GLFW_KEY_F);
    else if (action == "focus") {  // a click at the middle of the window
        const VkExtent2D size = window.framebuffer_size();
        input.clicked = true;
        input.click_x = 0.5 * size.width;
        input.click_y = 0.5 * size.height;
    }
    else throw CLI::ValidationError("--script", "unknown action '" + action + "'");
}

void write_screenshot(const std::filesystem::path& exr, const Renderer& renderer, const ViewerState& s,
                      const ViewCommand& c) {
    Image image = renderer.read_film();
    ImageMetadata metadata{{"fredholm:renderer", "fredholm view"},
                           {"fredholm:scene", c.scene.filename().string()},
                           {"fredholm:spp", std::to_string(s.spp)},
                           {"fredholm:colorspace", "scene-linear Rec.709"}};
    for (const SettingInfo& e : setting_table())  // the settings as the viewer has them now
        if (e.metadata_key) metadata.emplace(e.metadata_key, e.describe(s.settings));
    write_exr(exr, image, metadata);
    std::filesystem::path png = exr;
    png.replace_extension(".png");
    write_png(png, image, s.exposure_ev, s.tone_curve);
    std::fprintf(stderr, "fredholm view: wrote %s and %s (%ux%u, %u spp)\n", exr.string().c_str(),
                 png.string().c_str(), s.settings.width, s.settings.height, s.spp);
}

// Host and device memory after the first frame and after the last (a --frames run prints both: tests/soak/).
class MemoryWatch {
public:
    void after_frame() {
        last_ = {resident_memory_bytes(), vk::device_memory_in_use()};
        if (frames_++ == 0) first_ = last_;
    }
    std::string describe() const {
        const auto mib = [](uint64_t bytes) { return std::to_string((bytes + (1u << 19)) >> 20) + " MiB"; };
        return "memory after frame 1 and frame " + std::to_string(frames_) + ": host resident " + mib(first_.host) +
               ", " + mib(last_.host) + "; device " + mib(first_.device.bytes) + " in " +
               std::to_string(first_.device.allocations) + " allocations, " + mib(last_.device.bytes) + " in " +
               std::to_string(last_.device.allocations) + " allocations";
    }

private:
    struct Sample {
        uint64_t host = 0;
        vk::DeviceMemoryInUse device;
    };
    Sample first_, last_;
    uint64_t frames_ = 0;
};

// Sizes a time-sliced frame: how many pixels (one sample each) fit in the target time, from the last frames.
struct FrameSlicer {
    double target_seconds;
    uint32_t cursor = 0;                  // next pixel of the current pass
    double seconds_per_sample = 2e-6;     // a first guess (lavapipe, Cornell box), corrected after a frame

    uint32_t budget(uint32_t pixels) const {
        double n = target_seconds / seconds_per_sample;
        return uint32_t(std::clamp(n, std::min(1024.0, double(pixels)), double(pixels)));
    }
    void observe(uint32_t samples, double seconds) {
        if (samples < 256 || seconds <= 0) return;  // too small to time
        seconds_per_sample = 0.5 * seconds_per_sample + 0.5 * seconds / samples;
    }
};

}  // namespace

void add_view_options(CLI::App& app, ViewCommand& c) {
    RenderSettings& s = c.settings;
    s.width = 384;
    s.height = 384;
    app.add_option("scene", c.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
    app.add_option("--width", s.width, "initial window width")->check(CLI::Range(16u, 8192u));
    app.add_option("--height", s.height, "initial window height")->check(CLI::Range(16u, 8192u));
    add_setting_options(app, s, {"camera"});  // the camera to start from
    add_camera_pose_options(app, c.pose);
    add_setting_options(app, s, {"max-depth", "seed"});
    add_integrator_option(app, s);
    add_environment_options(app, s);  // --env, --background, --variant, --instancing: as render
    add_lens_options(app, s);
    add_animation_options(app, s);
    app.add_option("--spp-per-frame", c.spp_per_frame,
                   "whole samples per pixel added each frame (default: a slice of a pass sized to --frame-ms)")
        ->check(CLI::Range(1u, 1024u));
    app.add_option("--frame-ms", c.frame_ms, "target render time per frame when --spp-per-frame is not given")
        ->check(CLI::Range(5.0, 10000.0));
    app.add_option("--target-error", c.target_error, "stop adding samples once the image's estimated relative error "
                                                     "is at most this (the title shows the error and the time left)")
        ->check(CLI::Range(1e-6, 10.0));
    app.add_option("--frames", c.frames, "render this many frames without interaction, save --screenshot, exit");
    app.add_option("--screenshot", c.screenshot, "EXR written by P or after --frames (a PNG is written beside it)");
    add_tone_options(app, c.exposure_ev, c.tone_curve, "display");
    app.add_flag("--validate", c.validation, "enable Vulkan validation layers (also FREDHOLM_VALIDATION=1)");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
    app.add_option("--script", c.script)->group("");  // tests: e.g. resize,orbit during a --frames run
}

int run_view(const ViewCommand& c) {
    if (!c.screenshot.empty()) check_writable(c.screenshot);
    const std::vector<std::string> script = split_script(c.script);
    if (!script.empty() && c.frames == 0) throw CLI::ValidationError("--script", "needs --frames");

    PreparedScene prepared = prepare_scene(c.scene, c.settings);
    const Scene& scene = prepared.scene;
    const SceneCamera start = apply_camera_pose(choose_camera(scene, c.settings.camera), c.pose);
    const glm::dvec3 center = 0.5 * (scene.bounds_min + scene.bounds_max);
    const double radius = 0.5 * glm::length(scene.bounds_max - scene.bounds_min);

    ViewerWindow window(c.settings.width, c.settings.height, "fredholm view");
    auto context = make_present_context(c);
    std::unique_ptr<vk::Swapchain> swapchain;
    try {
        swapchain = std::make_unique<vk::Swapchain>(*context, window.create_surface(context->instance()),
                                                    window.framebuffer_size());
    } catch (const vk::PresentUnsupported& e) {
        throw DisplayUnavailable(std::string(e.what()) + "; use `fredholm render`");
    }
    FilmPresenter presenter(*context);

    ViewerState s{c.settings, ViewerCamera(start, center, radius), c.exposure_ev, c.tone_curve};
    s.settings.spp = std::max(c.spp_per_frame, 1u);  // bounds the wave size: one frame's samples
    FrameSlicer slicer{c.frame_ms * 1e-3};
    std::unique_ptr<Renderer> renderer;
    // Distance in focus for the surface seen at (x, y); where no surface is there, the orbit target's.
    auto focus_or_target = [&](double x, double y) {
        const SceneCamera camera = s.camera.scene_camera();
        try {
            return find_focus_distance(*context, prepared.packed, camera, s.settings.width, s.settings.height, x, y);
        } catch (const std::runtime_error& e) {
            const glm::dvec3 forward = -glm::normalize(glm::dvec3(camera.world_from_camera[2]));
            const double d = std::max(glm::dot(s.camera.target() - s.camera.eye(), forward), 1e-6);
            std::fprintf(stderr, "fredholm view: %s; focusing on the orbit target at %g\n", e.what(), d);
            return d;
        }
    };
    // The view's camera with its lens: a focus distance not yet known (autofocus) is found once and then kept, as
    // a camera's focus ring stays where it was set while the camera moves.
    auto lens_camera = [&] {
        const SceneCamera camera = s.camera.scene_camera();
        LensSettings& lens = s.settings.lens;
        if (!lens.on()) return camera;
        if (lens.focus_distance <= 0.0) {
            const double x = lens.focus_on_given ? lens.focus_on[0] + 0.5 : 0.5 * s.settings.width;
            const double y = lens.focus_on_given ? lens.focus_on[1] + 0.5 : 0.5 * s.settings.height;
            lens.focus_distance = focus_or_target(x, y);
            lens.focus_on_given = false;
        }
        return apply_lens(*context, prepared.packed, camera, s.settings);
    };
    // The error estimate of the film so far (reset with it), and the time since it was cleared, for the time left.
    RunningErrorEstimate estimate;
    auto film_cleared = Clock::now();
    auto restart_estimate = [&] {
        estimate.reset(size_t(s.settings.width) * s.settings.height);
        film_cleared = Clock::now();
        s.error = estimate.error();
        s.target_reached = false;
    };
    auto build = [&] {
        renderer.reset();
        s.settings.width = swapchain->extent().width;
        s.settings.height = swapchain->extent().height;
        check_render_fits(prepared, s.settings, *context, c.scene);
        renderer = std::make_unique<Renderer>(*context, prepared.packed, lens_camera(), s.settings);
        renderer->clear_film();
        s.spp = 0;
        slicer.cursor = 0;
        restart_estimate();
    };
    s.target_error = c.target_error;
    build();
    if (c.frames == 0) print_help();

    uint64_t nonfinite = 0;
    double samples_per_second = 0, ms_per_frame = 0;
    MemoryWatch memory;
    auto last_frame = Clock::now();
    for (uint32_t frame = 0; c.frames == 0 || frame < c.frames; ++frame) {
        window.poll();
        if (window.should_close()) break;
        WindowInput input = window.take_input();
        for (size_t i = 0; i < script.size(); ++i)  // action i at frame (i + 1) * frames / (actions + 1)
            if (frame == (i + 1) * c.frames / (script.size() + 1)) run_script_action(script[i], window, input);
        const double frame_seconds = seconds_since(last_frame);
        last_frame = Clock::now();
        apply_input(s, input, window, frame_seconds, c.scene, c.settings.camera, c.pose.given());
        if (s.quit) break;

        VkExtent2D size = window.framebuffer_size();
        if (size.width == 0 || size.height == 0) continue;  // minimised
        if (size.width != swapchain->extent().width || size.height != swapchain->extent().height) {
            swapchain->recreate(size);
            s.rebuild = true;
        }
        if (s.focus_request) {
            s.settings.lens.focus_distance = focus_or_target(s.focus_x, s.focus_y);
            s.settings.lens.focus_on_given = false;
            std::fprintf(stderr, "fredholm view: focus distance %g%s\n", s.settings.lens.focus_distance,
                         s.settings.lens.on() ? "" : " (open the aperture with F to see it)");
            s.focus_request = false;
            s.restart = true;
        }
        if (s.rebuild) build();
        else if (s.restart) {
            renderer->set_camera(lens_camera());
            renderer->clear_film();
            s.spp = 0;
            slicer.cursor = 0;
            restart_estimate();
        }
        s.rebuild = s.restart = false;

        const auto start_frame = Clock::now();
        const uint32_t pixels = s.settings.width * s.settings.height;
        RenderStats stats;
        stats.spp_done = s.spp;
        uint64_t samples = 0;
        if (s.target_reached) {
            // Nothing more to render until the view changes: wait for input instead of spinning.
            window.wait_events(0.1);
        } else if (c.spp_per_frame > 0) {
            stats = renderer->render_samples(s.spp, s.spp + c.spp_per_frame);
            samples = uint64_t(pixels) * c.spp_per_frame;
        } else {
            const uint32_t count = std::min(slicer.budget(pixels), pixels - slicer.cursor);
            stats = renderer->render_pixels(slicer.cursor, count, s.spp);
            slicer.cursor = (slicer.cursor + count) % pixels;
            samples = count;
            slicer.observe(count, stats.render_seconds);
        }
        s.spp = stats.spp_done;
        s.pass_fraction = s.target_reached ? 0.0 : double(slicer.cursor) / pixels;
        if (estimate.update(*renderer, s.spp)) {
            s.error = estimate.error();
            const double seconds = seconds_since(film_cleared), ratio = s.error / s.target_error;
            s.seconds_left = std::isfinite(ratio) ? std::max(0.0, seconds * (ratio * ratio - 1)) : 0.0;
            if (s.target_error > 0 && estimate.complete_batches() >= 3 && s.error <= s.target_error) {
                s.target_reached = true;
                std::fprintf(stderr, "fredholm view: target error %.3g%% reached at %u spp (%.3g%%) in %.1f s\n",
                             100 * s.target_error, s.spp, 100 * s.error, seconds);
            }
        }
        nonfinite += stats.nonfinite_samples;
        if (stats.render_seconds > 0) samples_per_second = double(samples) / stats.render_seconds;
        if (!presenter.present(renderer->film_buffer(), s.settings.width, s.settings.height, s.exposure_ev,
                               s.tone_curve, *swapchain))
            swapchain->recreate(window.framebuffer_size());
        ms_per_frame = 1e3 * seconds_since(start_frame);
        memory.after_frame();
        window.set_title(make_title(s, samples_per_second, ms_per_frame));

        if (s.screenshot) {
            write_screenshot(c.screenshot.empty() ? std::filesystem::path("fredholm_view.exr") : c.screenshot,
                             *renderer, s, c);
            s.screenshot = false;
        }
    }
    if (c.frames > 0 && !c.screenshot.empty()) write_screenshot(c.screenshot, *renderer, s, c);
    std::fprintf(stderr, "fredholm view: %ux%u, %u spp, %.2f Msamples/s, %.0f ms/frame on %s; %llu non-finite samples; "
                         "estimated relative error %.3g%%\n",
                 s.settings.width, s.settings.height, s.spp, samples_per_second * 1e-6, ms_per_frame,
                 context->device_name().c_str(), (unsigned long long)nonfinite, 100 * s.error);
    if (c.frames > 0) std::fprintf(stderr, "fredholm view: %s\n", memory.describe().c_str());
    renderer.reset();
    swapchain.reset();
    if (context->validation_message_count() > 0) {
        std::fprintf(stderr, "fredholm: error: %u Vulkan validation message(s)\n", context->validation_message_count());
        return 1;
    }
    return 0;
}

}  // namespace fh
