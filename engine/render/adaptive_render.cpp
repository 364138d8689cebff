// Adaptive sampling: the pilot, the allocation, the image and its own error; see adaptive_render.h.
#include "render/adaptive_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>

#include "render/film.h"

namespace fh {
namespace {

constexpr uint32_t TARGET_PILOT_SPP = 8;
constexpr uint32_t MIN_PILOT_SPP = 4;  // 4 batches of one sample: error_estimate.h needs 2 complete ones, 3 to trust
constexpr uint32_t MAX_PILOT_SPP = 64;
constexpr uint32_t QUARTERS = 4;
// A target's first allocation aims at this times the target: the pilot's prediction (V / n) is pessimistic where
// Owen-scrambled Sobol' converges faster than 1 / n (stopped on the prediction alone, the images' true errors came out
// 0.71 to 0.94 of the target on five scenes; tests/bench/RESULTS.md "2026-11-29: adaptive sampling"), and the top-ups
// from the image's own estimate add what is missing in small steps.
constexpr double FIRST_AIM = 1.3;
// A sample's work besides its paths' vertices and shadow rays (generate, accumulate, advance: 0.037 us), in
// PATH_WORK_* units (layout.h, about 0.3 us each), from the same measurement.
constexpr double SAMPLE_OVERHEAD_WORK = 0.15;

// What the pilot's film and batches say per pixel: its mean luminance, one sample's variance (the variance of the
// mean times the samples) and one sample's work.
PilotEstimate read_pilot(const Renderer& renderer, const ErrorBatches& batches, uint32_t spp) {
    PilotEstimate pilot;
    pilot.width = int(renderer.settings().film_width());
    pilot.height = int(renderer.settings().film_height());
    pilot.spp = spp;
    const Image image = renderer.read_film();
    const std::vector<float> variance = pixel_variance(batches);
    const std::vector<uint32_t> work = renderer.read_pixel_work();
    pilot.luminance.resize(variance.size());
    pilot.sample_variance.resize(variance.size());
    pilot.sample_cost.resize(variance.size());
    for (size_t i = 0; i < variance.size(); ++i) {
        pilot.luminance[i] = pixel_luminance(image, i);
        pilot.sample_variance[i] = double(variance[i]) * spp;
        pilot.sample_cost[i] = double(work[i]) / spp + SAMPLE_OVERHEAD_WORK;
    }
    return pilot;
}

// Each pixel's samples [0, n) in four quarters (n a power of two, at least 4) and the exact luminance sum of each, as
// the uniform estimate keeps its batches (error_estimate.h), for the image's error from its own samples: held as
// batches of one "sample" (the quarter's sum), so pixel_variance gives the variance of their mean, (n / 4)^2 times
// the pixel's.
class Quarters {
public:
    explicit Quarters(size_t pixels) : sums_(make_error_batches(pixels, 0)) { sums_.end_sample = QUARTERS; }
    void add(size_t pixel, uint32_t quarter, ExactSum sum) { sums_.sums[pixel * MAX_ERROR_BATCHES + quarter] += sum; }
    // The pixel's samples multiply by `factor` (a power of two): its old quarters fill its new first ones.
    void grow(size_t p, uint32_t factor) {
        ExactSum merged[QUARTERS] = {};
        for (uint32_t q = 0; q < QUARTERS; ++q) merged[q / std::min(factor, QUARTERS)] += at(p, q);
        for (uint32_t q = 0; q < QUARTERS; ++q) at(p, q) = merged[q];
    }
    std::vector<float> variance(const std::vector<uint32_t>& counts) const {
        std::vector<float> v = pixel_variance(sums_);
        for (size_t p = 0; p < v.size(); ++p) v[p] /= float(counts[p] / QUARTERS) * float(counts[p] / QUARTERS);
        return v;
    }

private:
    ExactSum& at(size_t p, uint32_t q) { return sums_.sums[p * MAX_ERROR_BATCHES + q]; }
    ErrorBatches sums_;
};

// The film's luminance, and what each chunk of samples added to it.
struct FilmWatch {
    std::vector<ExactSum> before;
    // Adds what entries [first, first + count) of `order` gained since the last look to their quarter of chunk
    // [sample, ...): quarter sample * 4 / counts[p].
    void take(const Renderer& renderer, const std::vector<uint32_t>& order, uint32_t first, uint32_t count,
              uint32_t sample, const std::vector<uint32_t>& counts, Quarters& quarters) {
        const std::vector<ExactSum> now = film_luminance(renderer.read_film_state());
        for (uint32_t e = first; e < first + count; ++e) {
            const uint32_t p = order[e];
            quarters.add(p, uint32_t(uint64_t(sample) * QUARTERS / counts[p]), subtract_sums(now[p], before[p]));
        }
        before = now;
    }
};

// How much each tile grows for an image whose error is `ratio` times its target (see render_adaptive's top-up):
// factors per tile (1: stays), within max_spp.
std::vector<uint32_t> plan_growth(const SampleAllocation& a, double ratio, uint32_t max_spp) {
    const double needed = ratio * ratio;  // how far the MSE must fall
    std::vector<uint32_t> growth(a.tile_count(), 1);
    const auto fits = [&](uint32_t t, uint32_t f) { return uint64_t(a.tile_samples(t)) * f <= max_spp; };
    if (needed > 2) {
        uint32_t factor = 2;
        while (factor < 64 && double(factor) * std::sqrt(2.0) < needed) factor *= 2;
        for (uint32_t t = 0; t < growth.size(); ++t) {
            uint32_t f = factor;
            while (f > 1 && !fits(t, f)) f /= 2;
            growth[t] = f;
        }
        return growth;
    }
    std::vector<uint32_t> by_worth(a.tile_count());
    std::iota(by_worth.begin(), by_worth.end(), 0u);
    std::stable_sort(by_worth.begin(), by_worth.end(), [&](uint32_t s, uint32_t t) {
        return a.tile_weights[s] / a.tile_samples(s) > a.tile_weights[t] / a.tile_samples(t);
    });
    const size_t wanted = size_t(std::ceil(std::min(1.0, 2.0 * (1.0 - 1.0 / needed)) * double(by_worth.size())));
    size_t taken = 0;
    for (uint32_t t : by_worth) {
        if (taken == wanted) break;
        if (fits(t, 2)) growth[t] = 2, ++taken;
    }
    return growth;
}

// The image pass: the film rendered afresh with the render's seed, each tile its count, in chunks that lie in one
// quarter of every pixel they cover (so each pixel's quarters are known), and a target's top-ups.
class Pass {
public:
    using Report = std::function<bool(uint64_t samples_done)>;  // false: interrupted
    Pass(Renderer& renderer, SampleAllocation& allocation, uint64_t samples_before, Report report,
         std::function<bool()> out_of_time)
        : renderer_(renderer), a_(allocation), listed_(allocation.order), quarters_(allocation.samples.size()),
          watch_{std::vector<ExactSum>(allocation.samples.size(), 0)}, done_(samples_before),
          report_(std::move(report)), out_of_time_(std::move(out_of_time)) {
        renderer_.clear_film();
        renderer_.set_pixel_order(listed_);
    }

    // Count level by count level: pixels with at least levels[k] samples are the first level_pixels[k] of the order.
    void render_levels() {
        uint32_t begin = 0;
        for (size_t k = 0; k < a_.levels.size(); ++k) {
            render_range(0, a_.level_pixels[k], begin, a_.levels[k], a_.levels[k] / QUARTERS);
            begin = a_.levels[k];
        }
    }

    // More samples for an image whose error is `ratio` times its target, where the pilot valued them (plan_growth):
    // nothing when they were added, else why none could be (the sample limit: no tile can grow within `max_spp`; the
    // time limit: they would take more than `samples_left` samples' time).
    std::optional<StopReason> top_up(double ratio, uint32_t max_spp, double samples_left) {
        const std::vector<uint32_t> growth = plan_growth(a_, ratio, max_spp);
        uint64_t added = 0;
        std::vector<uint32_t> growing, resting;
        for (uint32_t t = 0; t < growth.size(); ++t) {
            (growth[t] > 1 ? growing : resting).push_back(t);
            added += uint64_t(a_.tile_samples(t)) * (growth[t] - 1) * a_.tile_pixels(t);
        }
        if (growing.empty()) return StopReason::samples;
        if (double(added) > samples_left) return StopReason::time;
        // The growing tiles first, in runs of one count and one growth, each run rendered from its count up.
        std::stable_sort(growing.begin(), growing.end(), [&](uint32_t s, uint32_t t) {
            const uint32_t ns = a_.tile_samples(s), nt = a_.tile_samples(t);
            return ns != nt ? ns > nt : growth[s] > growth[t];
        });
        std::vector<uint32_t> tiles(growing);
        tiles.insert(tiles.end(), resting.begin(), resting.end());
        listed_ = a_.pixels_of(tiles);
        renderer_.set_pixel_order(listed_);
        for (size_t i = 0, entry = 0; i < growing.size() && !stop_;) {
            const uint32_t n = a_.tile_samples(growing[i]), f = growth[growing[i]];
            size_t end = i, run_pixels = 0;
            for (; end < growing.size() && a_.tile_samples(growing[end]) == n && growth[growing[end]] == f; ++end)
                run_pixels += a_.tile_pixels(growing[end]);
            for (size_t e = entry; e < entry + run_pixels; ++e) {
                quarters_.grow(listed_[e], f);
                a_.samples[listed_[e]] = n * f;
            }
            render_range(uint32_t(entry), uint32_t(run_pixels), n, n * f, n * f / QUARTERS);
            entry += run_pixels;
            i = end;
        }
        a_.order_by_samples();
        return std::nullopt;
    }

    std::vector<float> variance() const { return quarters_.variance(a_.samples); }
    double error() const { return relative_error(renderer_.read_film(), variance()); }
    const std::optional<StopReason>& stop() const { return stop_; }  // an interrupt or the time limit
    const RenderStats& stats() const { return stats_; }

private:
    // Samples [begin, end) of entries [first, first + count), in chunks aligned to multiples of `chunk`.
    void render_range(uint32_t first, uint32_t count, uint32_t begin, uint32_t end, uint32_t chunk) {
        for (uint32_t s = begin, next = 0; s < end && !stop_; s = next) {
            next = std::min(end, (s / chunk + 1) * chunk);
            uint32_t reached = s;
            const RenderStats part = renderer_.render_listed(first, count, s, next, [&](uint32_t spp_done, uint32_t) {
                done_ += uint64_t(spp_done - reached) * count;
                reached = spp_done;
                if (!report_(done_)) stop_ = StopReason::interrupted;
                else if (out_of_time_()) stop_ = StopReason::time;
                return !stop_;
            });
            add_stats(stats_, part);
            watch_.take(renderer_, listed_, first, count, s, a_.samples, quarters_);
        }
    }

    Renderer& renderer_;
    SampleAllocation& a_;
    std::vector<uint32_t> listed_;  // the pixel list the waves take
    Quarters quarters_;
    FilmWatch watch_;
    uint64_t done_;
    Report report_;
    std::function<bool()> out_of_time_;
    std::optional<StopReason> stop_;
    RenderStats stats_;
};

}  // namespace

uint32_t pilot_spp(const AdaptiveGoal& goal) {
    if (goal.target_error > 0) return std::clamp(goal.max_spp, MIN_PILOT_SPP, TARGET_PILOT_SPP);
    uint32_t spp = MIN_PILOT_SPP;
    while (spp * 2 <= std::min(goal.mean_spp / 8, MAX_PILOT_SPP)) spp *= 2;
    return spp;
}

uint32_t pilot_seed(uint32_t seed) {
    const uint32_t mixed = (seed ^ 0x5bd1e995u) * 0x9e3779b1u + 0x7f4a7c15u;
    return mixed != seed ? mixed : mixed + 1u;
}

AdaptiveRenderResult render_adaptive(Renderer& renderer, const AdaptiveGoal& goal, const EstimatedProgress& progress) {
    const uint32_t seed = renderer.settings().seed;
    const uint64_t pixels = uint64_t(renderer.settings().film_width()) * renderer.settings().film_height();
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    AdaptiveRenderResult r;
    r.pilot_spp = pilot_spp(goal);
    r.pilot_seed = pilot_seed(seed);
    r.pilot_samples = uint64_t(r.pilot_spp) * pixels;
    const bool target = goal.target_error > 0;
    uint32_t planned_spp = target ? goal.max_spp : goal.mean_spp;  // on average, for the progress line
    double error = NAN;
    const Pass::Report report = [&](uint64_t samples) {
        return !progress || progress({uint32_t(samples / pixels), planned_spp, error, elapsed()});
    };

    // The pilot: a uniform render with its own seed, batch by batch for its variances (not limited by --max-seconds).
    renderer.set_seed(r.pilot_seed);
    renderer.clear_film();
    ErrorBatches batches = make_error_batches(pixels, 0);
    const EstimatedRenderResult pilot_render =
        render_estimated(renderer, batches, RenderGoal{r.pilot_spp, 0, 0},
                         [&](const EstimatedRenderStatus& status) { return report(status.spp_done * pixels); });
    add_stats(r.stats, pilot_render.stats);
    r.pilot_seconds = pilot_render.stats.render_seconds;
    renderer.set_seed(seed);
    if (pilot_render.stop == StopReason::interrupted) {
        r.stop = StopReason::interrupted;
        r.error = NAN;
        return r;
    }
    const PilotEstimate pilot = read_pilot(renderer, batches, r.pilot_spp);

    // The allocation: a budget's time, or the least predicted to reach the target within the limits.
    const double seconds_per_sample = r.pilot_seconds / double(r.pilot_samples);  // at the pilot's speed, evenly spread
    SampleAllocation allocation;
    if (target) {
        uint64_t most = pixels * goal.max_spp;
        if (goal.max_seconds > 0)
            most = std::min(most, uint64_t(std::max(goal.max_seconds - elapsed(), 0.0) / seconds_per_sample));
        allocation = allocate_for_target(pilot, goal.target_error * FIRST_AIM, std::max(most, pixels), goal.max_spp);
    } else {
        allocation = allocate_samples(pilot, pixels * std::max<uint64_t>(goal.mean_spp - r.pilot_spp, 1), goal.max_spp);
    }
    planned_spp = uint32_t((allocation.total_samples() + r.pilot_samples + pixels - 1) / pixels);

    // The image, and a target's top-ups while the image's own estimate is above it.
    Pass pass(renderer, allocation, r.pilot_samples, report, [&] {
        return goal.max_seconds > 0 && elapsed() >= goal.max_seconds;
    });
    pass.render_levels();
    if (!pass.stop()) error = pass.error();
    while (target && !pass.stop() && error > goal.target_error) {
        const double seconds_left = goal.max_seconds > 0 ? goal.max_seconds - elapsed() : INFINITY;
        const std::optional<StopReason> limit =
            pass.top_up(error / goal.target_error, goal.max_spp, seconds_left / seconds_per_sample);
        if (limit) {
            r.stop = *limit;
            break;
        }
        if (!pass.stop()) error = pass.error();
    }
    if (pass.stop()) r.stop = *pass.stop();
    else if (target && error <= goal.target_error) r.stop = StopReason::target;
    add_stats(r.stats, pass.stats());

    // What the image holds: each pixel's samples, and its variance from its quarters (from the pilot's variance when
    // the render stopped early and some quarters are missing).
    const std::vector<gpu::FilmPixel> film = renderer.read_film_state();
    std::vector<uint32_t> held(film.size());
    for (size_t i = 0; i < film.size(); ++i) held[i] = film[i].sample_count;
    r.variance = pass.stop() ? allocated_variance(pilot, held) : pass.variance();
    r.error = relative_error(renderer.read_film(), r.variance);
    r.image_samples = std::accumulate(held.begin(), held.end(), uint64_t(0));
    r.min_spp = *std::min_element(held.begin(), held.end());
    r.max_spp = *std::max_element(held.begin(), held.end());
    r.stats.spp_done = r.max_spp;
    r.stats.render_seconds = elapsed();
    return r;
}

}  // namespace fh
