// Key bindings and mouse mapping of the viewer, its window title, help text and "print as render command".
#include "app/view/viewer_controls.h"

#include <GLFW/glfw3.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/cli/camera_options.h"
#include "render/camera/lens.h"

namespace fh {
namespace {

constexpr double FLY_RADII_PER_SECOND = 0.5;
constexpr float EXPOSURE_STEP_EV = 0.5f;
constexpr uint32_t TOP_LIMITED_DEPTH = 16;  // [ from unlimited goes here; ] from here goes to unlimited

const char* on_off(bool value) { return value ? "on" : "off"; }
const char* curve_name(ToneCurve curve) { return curve == ToneCurve::aces ? "aces" : "clamp"; }

std::string depth_text(uint32_t depth) { return depth == 0 ? "inf" : std::to_string(depth); }

// F steps through these f-numbers; 0 is the pinhole.
constexpr double F_STOPS[] = {0.0, 16.0, 8.0, 4.0, 2.0, 1.0};

// The next f-number after the lens's (from a pinhole or an --aperture-radius: the first f-stop).
double next_f_stop(const LensSettings& lens) {
    if (lens.aperture_radius > 0.0) return F_STOPS[1];
    const size_t count = std::size(F_STOPS);
    for (size_t i = 0; i < count; ++i)
        if (lens.f_number == F_STOPS[i]) return F_STOPS[(i + 1) % count];
    return F_STOPS[0];
}

std::string lens_text(const LensSettings& lens) {
    if (!lens.on()) return "pinhole";
    char text[64];
    if (lens.f_number > 0.0) std::snprintf(text, sizeof text, "f/%g", lens.f_number);
    else std::snprintf(text, sizeof text, "r %g", lens.aperture_radius);
    std::string out = text;
    if (lens.focus_distance > 0.0) {
        std::snprintf(text, sizeof text, " @ %.3g", lens.focus_distance);
        out += text;
    }
    return out;
}

}  // namespace

void apply_input(ViewerState& s, const WindowInput& input, const ViewerWindow& window, double frame_seconds,
                 const std::filesystem::path& scene, int camera_index, bool pose_given) {
    if (input.orbit_dx != 0 || input.orbit_dy != 0) {
        s.camera.orbit(input.orbit_dx, input.orbit_dy);
        s.restart = true;
    }
    if (input.pan_dx != 0 || input.pan_dy != 0) {
        s.camera.pan(input.pan_dx, input.pan_dy, double(window.framebuffer_size().height));
        s.restart = true;
    }
    if (input.wheel != 0) {
        s.camera.zoom(input.wheel);
        s.restart = true;
    }
    const double step = FLY_RADII_PER_SECOND * std::min(frame_seconds, 0.25);
    const double forward = (window.key_down(GLFW_KEY_W) ? step : 0) - (window.key_down(GLFW_KEY_S) ? step : 0);
    const double right = (window.key_down(GLFW_KEY_D) ? step : 0) - (window.key_down(GLFW_KEY_A) ? step : 0);
    const double up = (window.key_down(GLFW_KEY_E) ? step : 0) - (window.key_down(GLFW_KEY_Q) ? step : 0);
    if (forward != 0 || right != 0 || up != 0) {
        s.camera.fly(forward, right, up);
        s.restart = true;
    }
    for (int key : input.pressed) {
        switch (key) {
            case GLFW_KEY_R: s.camera.reset(); s.restart = true; break;
            case GLFW_KEY_LEFT_BRACKET:  // unlimited (0) sits above the top limited depth
                s.settings.max_depth = s.settings.max_depth == 0 ? TOP_LIMITED_DEPTH : std::max(s.settings.max_depth - 1, 1u);
                s.rebuild = true;
                break;
            case GLFW_KEY_RIGHT_BRACKET:
                // BDPT stores light vertices per path: its depth stays bounded.
                if (connects_subpaths(s.settings.integrator) && s.settings.max_depth >= TOP_LIMITED_DEPTH) break;
                if (s.settings.max_depth != 0)
                    s.settings.max_depth = s.settings.max_depth >= TOP_LIMITED_DEPTH ? 0 : s.settings.max_depth + 1;
                s.rebuild = true;
                break;
            case GLFW_KEY_EQUAL: case GLFW_KEY_KP_ADD: s.exposure_ev += EXPOSURE_STEP_EV; break;
            case GLFW_KEY_MINUS: case GLFW_KEY_KP_SUBTRACT: s.exposure_ev -= EXPOSURE_STEP_EV; break;
            case GLFW_KEY_T: s.tone_curve = s.tone_curve == ToneCurve::aces ? ToneCurve::clamp : ToneCurve::aces; break;
            case GLFW_KEY_N:
                if (connects_subpaths(s.settings.integrator)) {
                    std::fprintf(stderr, "fredholm view: bidirectional path tracing always samples lights; N is off\n");
                    break;
                }
                s.settings.nee = !s.settings.nee;
                s.rebuild = true;
                break;
            case GLFW_KEY_U: s.settings.russian_roulette = !s.settings.russian_roulette; s.rebuild = true; break;
            case GLFW_KEY_P: s.screenshot = true; break;
            case GLFW_KEY_F: {
                if (s.settings.integrator != Integrator::path) {  // light subpaths have no thin lens yet
                    std::fprintf(stderr, "fredholm view: light tracing has no thin lens yet; the aperture stays a pinhole\n");
                    break;
                }
                LensSettings& lens = s.settings.lens;
                const bool was_on = lens.on();
                lens.f_number = next_f_stop(lens);
                lens.aperture_radius = 0.0;
                if (lens.on() != was_on) s.rebuild = true;  // the stages compile the lens in or out
                else s.restart = true;
                std::fprintf(stderr, "fredholm view: aperture %s\n", lens_text(lens).c_str());
                break;
            }
            case GLFW_KEY_C:
                std::printf("%s\n", make_render_command(s, scene, camera_index, pose_given).c_str());
                std::fflush(stdout);
                break;
            case GLFW_KEY_H: case GLFW_KEY_F1: print_help(); break;
            case GLFW_KEY_ESCAPE: s.quit = true; break;
            default: break;
        }
    }
    if (input.clicked) {
        s.focus_request = true;
        s.focus_x = input.click_x;
        s.focus_y = input.click_y;
    }
    // Without roulette and without a depth limit a path in a closed scene never ends: cap it.
    if (!s.settings.russian_roulette && s.settings.max_depth == 0) {
        s.settings.max_depth = TOP_LIMITED_DEPTH;
        std::fprintf(stderr, "fredholm view: Russian roulette off: max depth set to %u\n", TOP_LIMITED_DEPTH);
    }
}

// "err 1.23%", with a target "err 1.23% (target 1%: 12 s left)" or "(target 1% reached)".
std::string error_text(const ViewerState& s) {
    if (!std::isfinite(s.error)) return "err estimating";
    char text[96];
    if (s.target_error <= 0) std::snprintf(text, sizeof text, "err %.3g%%", 100 * s.error);
    else if (s.target_reached) std::snprintf(text, sizeof text, "err %.3g%% (target %.3g%% reached)", 100 * s.error, 100 * s.target_error);
    else std::snprintf(text, sizeof text, "err %.3g%% (target %.3g%%: %.0f s left)", 100 * s.error, 100 * s.target_error, s.seconds_left);
    return text;
}

std::string make_title(const ViewerState& s, double samples_per_second, double ms_per_frame) {
    char title[512];
    std::snprintf(title, sizeof(title),
                  "fredholm view | %.2f spp | %s | %.2f Msamples/s | %.0f ms/frame | %ux%u depth %s NEE %s RR %s %s | "
                  "EV %+.1f %s | drag orbit, shift/right drag pan, wheel zoom, WASDQE fly, H help",
                  s.spp + s.pass_fraction, error_text(s).c_str(), samples_per_second * 1e-6, ms_per_frame, s.settings.width, s.settings.height,
                  depth_text(s.settings.max_depth).c_str(), on_off(s.settings.nee), on_off(s.settings.russian_roulette),
                  lens_text(s.settings.lens).c_str(), s.exposure_ev, curve_name(s.tone_curve));
    return title;
}

void print_help() {
    std::fprintf(stderr,
                 "fredholm view controls:\n"
                 "  left drag           orbit around the target\n"
                 "  right/middle drag   pan (also shift + left drag)\n"
                 "  wheel               zoom towards the target\n"
                 "  W A S D / Q E       fly forward, left, back, right / down, up\n"
                 "  R                   reset to the starting camera\n"
                 "  [ ]                 max depth down / up: 1 .. 16, unlimited (Russian roulette ends paths)\n"
                 "  + -                 exposure up / down by half a stop (display only)\n"
                 "  T                   tone curve: aces / clamp (display only)\n"
                 "  N  U                toggle next-event estimation / Russian roulette\n"
                 "  F                   aperture: pinhole, f/16, f/8, f/4, f/2, f/1 (depth of field)\n"
                 "  click               focus on the surface under the cursor\n"
                 "  P                   screenshot: linear EXR of the accumulated film + PNG\n"
                 "  C                   print this view as a `fredholm render` command line\n"
                 "  H  F1               this help;  Esc quits\n"
                 "Any camera or sampling change restarts accumulation.\n");
}

std::string make_render_command(const ViewerState& s, const std::filesystem::path& scene, int camera_index,
                                bool pose_given) {
    const RenderSettings& r = s.settings;
    std::string command = "fredholm render " + scene.string() + " -o render.exr --png render.png";
    command += " --width " + std::to_string(r.width) + " --height " + std::to_string(r.height);
    command += " --spp " + std::to_string(std::max(s.spp, 64u));
    command += " --max-depth " + std::to_string(r.max_depth);
    command += std::string(" --nee ") + on_off(r.nee) + " --rr " + on_off(r.russian_roulette);
    if (r.integrator != Integrator::path) command += std::string(" --integrator ") + to_string(r.integrator);
    char exposure[32];
    std::snprintf(exposure, sizeof(exposure), "%g", s.exposure_ev);
    command += std::string(" --exposure ") + exposure + " --tonemap " + curve_name(s.tone_curve);
    if (camera_index >= 0) command += " --camera " + std::to_string(camera_index);
    if (!s.camera.unchanged() || pose_given)
        command.append(" ").append(format_camera_pose(s.camera.eye(), s.camera.target(), s.camera.up(), s.camera.yfov_degrees()));
    if (r.lens.on()) command.append(" ").append(format_lens_options(r.lens));
    return command;
}

}  // namespace fh
