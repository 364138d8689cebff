// What the viewer can change while it runs (camera, depth, sampling switches, display), and the key bindings.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "app/view/viewer_camera.h"
#include "app/view/viewer_window.h"
#include "io/tone_curve.h"
#include "render/settings.h"

namespace fh {

struct ViewerState {
    RenderSettings settings;   // width/height follow the window
    ViewerCamera camera;
    float exposure_ev = 0.0f;
    ToneCurve tone_curve = ToneCurve::aces;
    uint32_t spp = 0;          // whole samples per pixel accumulated since the last restart
    double pass_fraction = 0;  // share of the pixels that already have sample spp + 1 (time-sliced frames)
    bool restart = false;      // camera moved: clear the film
    bool rebuild = false;      // a setting the renderer is built with changed
    bool screenshot = false;   // P pressed
    bool focus_request = false;  // clicked: focus on the surface at (focus_x, focus_y), framebuffer pixels
    double focus_x = 0, focus_y = 0;
    bool quit = false;
    double error = 0;             // the film's estimated relative error (NaN until it can be estimated)
    double target_error = 0;      // --target-error (0: none)
    double seconds_left = 0;      // to the target, assuming the error falls as 1 / sqrt(time)
    bool target_reached = false;  // no more samples until the view changes
};

// Applies one frame's input: mouse moves, wheel, key presses, held fly keys (over `frame_seconds`).
void apply_input(ViewerState& state, const WindowInput& input, const ViewerWindow& window, double frame_seconds,
                 const std::filesystem::path& scene, int camera_index, bool pose_given);

std::string make_title(const ViewerState& state, double samples_per_second, double ms_per_frame);
void print_help();
// A `fredholm render` command line that reproduces the current view.
std::string make_render_command(const ViewerState& state, const std::filesystem::path& scene, int camera_index,
                                bool pose_given);

}  // namespace fh
