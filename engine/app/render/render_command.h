// `fredholm render`: one scene, one camera, to EXR (plus optional PNG preview and JSON statistics).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "app/cli/camera_options.h"
#include "render/aov_image.h"
#include "io/tone_curve.h"
#include "render/renderer.h"
#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

struct RenderCommand {
    std::filesystem::path scene;
    std::filesystem::path output;
    std::filesystem::path png;
    std::filesystem::path stats;
    RenderSettings settings;
    float exposure_ev = 0.0f;
    ToneCurve tone_curve = ToneCurve::aces;
    bool validation = false;
    std::string device;
    bool quiet = false;
    bool resume = false;                // continue a render written by fredholm render instead of starting afresh
    std::filesystem::path resume_file;  // ... this one; empty: the output file itself
    CameraPoseOptions pose;             // --look-from/--look-at/--up/--yfov (as printed by the viewer)
    std::string frames;                 // --frames A:B: a sequence, frame f at time f / fps; "" one image
    double fps = 24.0;                  // --fps
    uint32_t first_sample = 0;          // --samples A:B: sample indices [A, B) of every pixel (B is settings.spp)
    bool sample_range = false;          // --samples given
    std::string crop;                   // --crop X0,Y0,X1,Y1 as given (checked against the image size when run)
    double target_error = 0;            // --target-error: stop once the relative error estimate is at most this
    uint32_t max_spp = 0;               // --max-spp: the sample limit with a target (0: not given)
    double max_seconds = 0;             // --max-seconds: stop at the first sample index past this (0: none)
    bool adaptive = false;              // --adaptive: a pilot, then each pixel its own samples (app/render/render_passes.h)
    std::string aov_list;               // --aov as given
    AovChoice aovs;                     // ... parsed
};

void add_render_options(CLI::App& app, RenderCommand& command);
// Returns the process exit code (0, or 130 when interrupted after writing the partial image). With --frames, renders
// each frame in turn (the scene reloaded, posed and its BVH rebuilt per frame) and stops after the frame in progress
// when interrupted.
int run_render(const RenderCommand& command);

}  // namespace fh
