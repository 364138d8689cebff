// The batch-by-batch render loop; see estimated_render.h.
#include "render/estimated_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "render/film.h"

namespace fh {
void add_stats(RenderStats& into, const RenderStats& part) {
    into.spp_done = part.spp_done;
    into.render_seconds += part.render_seconds;
    for (const auto& [stage, seconds] : part.stage_seconds) into.stage_seconds[stage] += seconds;
    into.traced_rays += part.traced_rays;
    into.traced_shadow_rays += part.traced_shadow_rays;
    into.nonfinite_samples += part.nonfinite_samples;
    into.escaped_rays += part.escaped_rays;
}

namespace {

// Complete batches needed before a target is trusted (from 6 samples on there are always 3 or more).
constexpr uint32_t MIN_BATCHES_FOR_TARGET = 3;

// The batch size a fresh render starts with: a whole wave's samples per pixel (so batch ends fall on wave ends and
// the waves stay as full as without an estimate), but no more than its planned samples need, so the final layout is
// batch_size_for(first, end) whatever the wave size.
uint32_t first_batch_size(const Renderer& renderer, uint32_t first, uint32_t end) {
    const uint64_t pixels = uint64_t(renderer.settings().film_width()) * renderer.settings().film_height();
    const uint64_t per_wave = std::max<uint64_t>(1, renderer.wave_capacity() / pixels);
    uint32_t size = 1;
    while (uint64_t(size) * 2 <= per_wave) size *= 2;
    return std::min(size, batch_size_for(first, end));
}

}  // namespace

const char* describe_stop(StopReason reason) {
    switch (reason) {
    case StopReason::samples: return "the sample limit";
    case StopReason::target: return "the target error";
    case StopReason::time: return "the time limit";
    case StopReason::interrupted: return "an interrupt";
    }
    return "?";
}

std::vector<ExactSum> film_luminance(const std::vector<gpu::FilmPixel>& film) {
    std::vector<ExactSum> y(film.size());
    for (size_t i = 0; i < film.size(); ++i) y[i] = luminance_sum(film[i]);
    return y;
}

double film_relative_error(const std::vector<gpu::FilmPixel>& film, const ErrorBatches& batches, int width, int height) {
    return relative_error(resolve_film(film, width, height), pixel_variance(batches));
}

EstimatedRenderResult render_estimated(Renderer& renderer, ErrorBatches& batches, const RenderGoal& goal,
                                       const EstimatedProgress& progress) {
    const int width = int(renderer.settings().film_width()), height = int(renderer.settings().film_height());
    EstimatedRenderResult result;
    result.stats.spp_done = batches.end_sample;
    std::vector<gpu::FilmPixel> film = renderer.read_film_state();
    std::vector<ExactSum> before = film_luminance(film);
    // The error is needed as the render goes only for a target; otherwise once, at the end. A target render starts
    // with batches of one sample, so the first check comes early; the batches (and the waves) grow with the render.
    const bool track_error = goal.target_error > 0;
    if (batches.end_sample == batches.first_sample && !track_error)
        coarsen(batches, first_batch_size(renderer, batches.first_sample, goal.end_sample));
    result.error = track_error ? film_relative_error(film, batches, width, height) : std::nan("");
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    bool stop_asked = false;
    uint32_t sample = batches.end_sample;
    while (sample < goal.end_sample && !stop_asked) {
        if (goal.target_error > 0 && complete_batch_count(batches) >= MIN_BATCHES_FOR_TARGET &&
            result.error <= goal.target_error) {
            result.stop = StopReason::target;
            break;
        }
        const uint32_t needed = batch_size_for(batches.first_sample, sample + 1);
        if (needed > batches.batch_size) coarsen(batches, needed);
        const uint32_t size = batches.batch_size;
        const uint32_t batch_end = uint32_t(std::min<uint64_t>(goal.end_sample, (uint64_t(sample) / size + 1) * size));
        uint32_t reached = sample;
        const RenderStats part = renderer.render_samples(sample, batch_end, [&](uint32_t done, uint32_t) {
            const bool at_sample_boundary = done != reached;
            reached = done;
            const double seconds = elapsed();
            bool go_on = !progress || progress({done, goal.end_sample, result.error, seconds});
            if (!go_on) {
                result.stop = StopReason::interrupted;
            } else if (goal.max_seconds > 0 && seconds >= goal.max_seconds) {
                result.stop = StopReason::time;
                go_on = false;
            }
            stop_asked = stop_asked || !go_on;
            return go_on || !at_sample_boundary;
        });
        add_stats(result.stats, part);
        if (part.spp_done > sample) {
            film = renderer.read_film_state();
            std::vector<ExactSum> now = film_luminance(film);
            std::vector<ExactSum> added(now.size());
            for (size_t i = 0; i < now.size(); ++i) added[i] = subtract_sums(now[i], before[i]);
            add_samples(batches, sample, part.spp_done, added);
            before = std::move(now);
            if (track_error) result.error = film_relative_error(film, batches, width, height);
            sample = part.spp_done;
        }
        if (part.spp_done < batch_end) break;  // stopped inside the batch
    }
    if (sample >= goal.end_sample && result.stop == StopReason::time) result.stop = StopReason::samples;
    if (!track_error) result.error = film_relative_error(film, batches, width, height);
    // The whole loop's time, with the batches' read-backs and estimates, not only the waves'.
    result.stats.render_seconds = elapsed();
    if (!stop_asked && result.stop != StopReason::target && goal.target_error > 0 &&
        complete_batch_count(batches) >= MIN_BATCHES_FOR_TARGET && result.error <= goal.target_error)
        result.stop = StopReason::target;
    return result;
}

void RunningErrorEstimate::reset(size_t pixels) {
    batches_ = make_error_batches(pixels, 0);
    before_.assign(pixels, 0);
    error_ = std::numeric_limits<double>::quiet_NaN();
}

bool RunningErrorEstimate::update(const Renderer& renderer, uint32_t spp) {
    if (spp <= batches_.end_sample) return false;
    uint32_t size = std::max(batches_.batch_size, batch_size_for(batches_.first_sample, spp));
    while (batches_.end_sample / size != (spp - 1) / size) size *= 2;
    if (size > batches_.batch_size) coarsen(batches_, size);
    if (spp % size != 0) return false;  // the batch is not complete yet: its samples wait in the film
    const std::vector<gpu::FilmPixel> film = renderer.read_film_state();
    std::vector<ExactSum> now = film_luminance(film), added(now.size());
    for (size_t i = 0; i < now.size(); ++i) added[i] = subtract_sums(now[i], before_[i]);
    add_samples(batches_, batches_.end_sample, spp, added);
    before_ = std::move(now);
    error_ = film_relative_error(film, batches_, int(renderer.settings().film_width()),
                                 int(renderer.settings().film_height()));
    return true;
}

}  // namespace fh
