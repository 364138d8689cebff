// A render that keeps its error estimate as it goes (render/error_estimate.h) and can stop at a target error or a
// time limit: the samples are rendered batch by batch, the film read back at each batch's end.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "render/error_estimate.h"
#include "render/renderer.h"

namespace fh {

struct RenderGoal {
    uint32_t end_sample = 0;      // render up to this sample index (--spp, or --max-spp with a target)
    double target_error = 0;      // stop once the image's relative error is at most this (0: no target)
    double max_seconds = 0;       // stop at the first sample index past this many seconds of rendering (0: none)
};

// Adds `part`'s times and counts to `into` (spp_done: part's).
void add_stats(RenderStats& into, const RenderStats& part);

// Why a render stopped.
enum class StopReason { samples, target, time, interrupted };
const char* describe_stop(StopReason reason);

struct EstimatedRenderStatus {
    uint32_t spp_done = 0, spp_total = 0;
    double error = 0;      // the image's relative error so far; NaN until it can be estimated
    double seconds = 0;    // rendering time so far in this run
};

// Called after each wave; return false to stop at the next sample index (an interrupt).
using EstimatedProgress = std::function<bool(const EstimatedRenderStatus&)>;

struct EstimatedRenderResult {
    RenderStats stats;
    StopReason stop = StopReason::samples;
    double error = 0;  // relative error of the image at the end (NaN: fewer than two complete batches)
};

// Renders samples batches.end_sample .. goal.end_sample into `renderer`'s film as it is (fresh or resumed), adding
// them to `batches` (which must describe the film's samples so far).
EstimatedRenderResult render_estimated(Renderer& renderer, ErrorBatches& batches, const RenderGoal& goal,
                                       const EstimatedProgress& progress = {});

// The error estimate of a film that grows a few samples at a time, outside render_estimated (the viewer): after each
// frame, update() adds the finished sample indices to the batches once a batch is complete (reading the film back
// then, not every frame). Samples a frame adds across a batch's end make the batches coarser, so a frame may add any
// number of them.
class RunningErrorEstimate {
public:
    void reset(size_t pixels);
    // The film holds samples [0, spp) of every pixel; returns true when the estimate changed.
    bool update(const Renderer& renderer, uint32_t spp);
    double error() const { return error_; }        // NaN until two batches are complete
    uint32_t complete_batches() const { return complete_batch_count(batches_); }

private:
    ErrorBatches batches_;
    std::vector<ExactSum> before_;  // the film's luminance at batches_.end_sample
    double error_ = 0;
};

// The luminance sums of every pixel of a film (error_estimate.h luminance_sum).
std::vector<ExactSum> film_luminance(const std::vector<gpu::FilmPixel>& film);

// The image's relative error from the film and its batches.
double film_relative_error(const std::vector<gpu::FilmPixel>& film, const ErrorBatches& batches, int width, int height);

}  // namespace fh
