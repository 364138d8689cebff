// Uniform and adaptive sampling for `fredholm render`; see render_passes.h.
#include "app/render/render_passes.h"

#include <cmath>
#include <cstdio>

#include "render/adaptive_render.h"

namespace fh {
namespace {
constexpr uint32_t DEFAULT_ADAPTIVE_MAX_SPP = 65536;  // a budget's limit per pixel (sample_allocation.h caps it lower)
}  // namespace

RenderOutcome render_uniform(const RenderCommand& c, Renderer& renderer, const FilmFile& saved, bool resumed,
                             const EstimatedProgress& progress) {
    const RenderSettings& s = renderer.settings();
    const uint64_t pixels = uint64_t(s.film_width()) * s.film_height();
    RenderOutcome out;
    // The error batches go on from the saved film's; a film saved before they existed gets no error estimate.
    out.estimate = !resumed || saved.has_batches;
    ErrorBatches batches = saved.has_batches ? saved.batches : make_error_batches(pixels, saved.end_sample);
    const RenderGoal goal{s.spp, c.target_error, c.max_seconds};
    const EstimatedRenderResult result = render_estimated(renderer, batches, goal, progress);
    out.stats = result.stats;
    out.stop = result.stop;
    out.error = out.estimate ? result.error : NAN;
    out.samples = pixels * (result.stats.spp_done - saved.end_sample);
    if (out.estimate)
        add_error_channels(batches, renderer.read_film(), out.channels, out.floats, out.metadata);
    out.samples_text = std::to_string(result.stats.spp_done) + " spp (" +
                       std::to_string(result.stats.spp_done - saved.end_sample) + " new)";
    return out;
}

RenderOutcome render_adaptive_pass(const RenderCommand& c, Renderer& renderer, const EstimatedProgress& progress) {
    AdaptiveGoal goal;
    goal.target_error = c.target_error;
    goal.mean_spp = c.target_error > 0 ? 0 : renderer.settings().spp;
    goal.max_spp = c.target_error > 0 ? renderer.settings().spp : DEFAULT_ADAPTIVE_MAX_SPP;  // with a target: --max-spp
    goal.max_seconds = c.max_seconds;
    AdaptiveRenderResult r = render_adaptive(renderer, goal, progress);
    RenderOutcome out;
    out.stats = r.stats;
    out.stop = r.stop;
    out.samples = r.pilot_samples + r.image_samples;
    if (r.stop == StopReason::interrupted && r.image_samples == 0) return out;  // stopped in the pilot
    out.estimate = true;
    out.error = r.error;
    const double pixels = double(renderer.settings().film_width()) * renderer.settings().film_height();
    const double mean = double(r.image_samples) / pixels;
    char text[160];
    std::snprintf(text, sizeof text, "pilot %u spp (seed %u), then %u to %u spp per pixel, %.4g on average",
                  r.pilot_spp, r.pilot_seed, r.min_spp, r.max_spp, mean);
    out.metadata["fredholm:adaptive"] = text;
    add_variance_layer(std::move(r.variance), r.error, out.floats, out.metadata);
    out.stats_json["adaptive"] = {{"pilot_spp", r.pilot_spp},     {"pilot_seed", r.pilot_seed},
                                  {"pilot_seconds", r.pilot_seconds}, {"min_spp", r.min_spp},
                                  {"max_spp", r.max_spp},         {"mean_spp", mean}};
    std::snprintf(text, sizeof text, "%.4g spp on average (%u to %u; pilot %u)", mean, r.min_spp, r.max_spp,
                  r.pilot_spp);
    out.samples_text = text;
    return out;
}

}  // namespace fh
