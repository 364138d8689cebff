// The sampling part of `fredholm render`: uniform (every pixel the same samples, with error batches, to a sample
// count or a target error) or adaptive (`--adaptive`: a pilot, then each pixel its own count). Each leaves the film in
// the Renderer and returns what the command writes beside it.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli/resume.h"
#include "app/render/render_command.h"
#include "io/exr.h"
#include "render/estimated_render.h"
#include "render/renderer.h"

namespace fh {

struct RenderOutcome {
    RenderStats stats;
    StopReason stop = StopReason::samples;
    bool estimate = false;      // the image has an error estimate
    double error = 0;           // ... its relative error (NaN: fewer than 2 batches)
    uint64_t samples = 0;       // rendered by this run (an adaptive render's pilot included)
    ExtraChannels channels;     // beside the film's: error batches
    FloatChannels floats;       // variance.Y
    ImageMetadata metadata;     // added to the render's: the error, the adaptive allocation
    nlohmann::json stats_json = nlohmann::json::object();  // added to --stats
    std::string samples_text;   // for the summary line: "64 spp (32 new)"
};

// Continues `saved` (or a fresh film from saved.end_sample) up to settings.spp or the target.
RenderOutcome render_uniform(const RenderCommand& c, Renderer& renderer, const FilmFile& saved, bool resumed,
                             const EstimatedProgress& progress);

// `--adaptive`: the budget is --spp samples per pixel on average, or the target error up to --max-spp.
RenderOutcome render_adaptive_pass(const RenderCommand& c, Renderer& renderer, const EstimatedProgress& progress);

}  // namespace fh
