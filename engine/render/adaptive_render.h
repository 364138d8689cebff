// Adaptive sampling (`fredholm render --adaptive`; engine/render/README.md "Adaptive sampling"): a pilot render with a
// seed of its own estimates each pixel's variance; the samples are shared out where they lower the image's relative
// error most (render/sample_allocation.h); then the image is rendered afresh with the render's own seed, each pixel its
// number of samples, waves taking the pixels from a list (lib/core/wave_pixels.glsl). The pilot's samples are not in
// the image: the decisions depend on samples independent of those they decide on, so each pixel's mean stays
// unbiased. A pixel given n samples holds exactly the samples a uniform render of n spp gives it.
#pragma once
#include <cstdint>
#include <vector>

#include "render/estimated_render.h"
#include "render/renderer.h"
#include "render/sample_allocation.h"

namespace fh {

struct AdaptiveGoal {
    uint32_t mean_spp = 0;       // the budget: samples per pixel on average, the pilot's included (with no target)
    double target_error = 0;     // or: the fewest samples predicted to reach this relative error
    uint32_t max_spp = 65536;    // no pixel gets more
    double max_seconds = 0;      // the render is sized to end by then, and stops there (0: no limit)
};

// The pilot's samples per pixel: an eighth of a budget, 4 to 64 (a power of two), or 8 for a target.
uint32_t pilot_spp(const AdaptiveGoal& goal);
// The pilot's seed: the render's, changed (so the pilot's Owen scrambles are independent of the image's).
uint32_t pilot_seed(uint32_t seed);

struct AdaptiveRenderResult {
    RenderStats stats;          // both passes (spp_done: the most samples a pixel got)
    StopReason stop = StopReason::samples;
    double error = 0;           // the image's relative error from the pilot's variances and each pixel's samples
    std::vector<float> variance;  // each pixel's variance of its mean luminance
    uint32_t pilot_spp = 0, pilot_seed = 0;
    uint32_t min_spp = 0, max_spp = 0;  // the fewest and most samples a pixel holds
    uint64_t image_samples = 0, pilot_samples = 0;
    double pilot_seconds = 0;
};

// Renders into `renderer` (built with settings.adaptive; its film is cleared first). Progress reports the samples
// per pixel on average, pilot included.
AdaptiveRenderResult render_adaptive(Renderer& renderer, const AdaptiveGoal& goal,
                                     const EstimatedProgress& progress = {});

}  // namespace fh
