// `fredholm view`: the interactive viewer, a window onto the same progressive path tracer as `render`.
#pragma once
#include <filesystem>
#include <string>

#include "app/cli/camera_options.h"
#include "io/tone_curve.h"
#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

struct ViewCommand {
    std::filesystem::path scene;
    RenderSettings settings;        // width/height: initial window size; spp: unused (see spp_per_frame)
    CameraPoseOptions pose;
    uint32_t spp_per_frame = 0;     // 0: time-sliced frames (a share of one pass, sized to frame_ms)
    double frame_ms = 60;           // target render time per frame when time-sliced
    uint32_t frames = 0;            // > 0: render this many frames without interaction, save, exit
    std::filesystem::path screenshot;  // EXR (+ PNG beside it) written by P, or after --frames
    float exposure_ev = 0.0f;
    ToneCurve tone_curve = ToneCurve::aces;
    bool validation = false;
    std::string device;
    std::string script;             // hidden, for tests: actions spread over a --frames run
    double target_error = 0;        // --target-error: stop adding samples at this estimated relative error
};

void add_view_options(CLI::App& app, ViewCommand& command);
// Returns the process exit code (0; 1 when Vulkan validation reported anything).
int run_view(const ViewCommand& command);

}  // namespace fh
