// Adaptive sampling's allocation; see sample_allocation.h.
#include "render/sample_allocation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace fh {
namespace {

constexpr double LUMINANCE_EPSILON = 0.01;  // as in relative_error (error_estimate.h)
constexpr int LADDER_STEPS_PER_OCTAVE = 1;

// The pilot's per-sample variance with unknown values (NaN) replaced by the largest known one.
std::vector<double> known_variance(const PilotEstimate& pilot) {
    double largest = 0;
    for (double v : pilot.sample_variance)
        if (std::isfinite(v)) largest = std::max(largest, v);
    std::vector<double> v(pilot.sample_variance);
    for (double& x : v) x = std::isfinite(x) ? std::max(x, 0.0) : largest;
    return v;
}

// The mean of `values` over each pixel's 3 x 3 neighbourhood (inside the image).
std::vector<double> box_3x3(const std::vector<double>& values, int width, int height) {
    std::vector<double> out(values.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double sum = 0;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= width || v >= height) continue;
                    sum += values[size_t(v) * width + u];
                    ++count;
                }
            out[size_t(y) * width + x] = sum / count;
        }
    return out;
}

// Each pixel's cost per sample over the 3 x 3 neighbourhood, relative to the mean (all 1 without costs).
std::vector<double> relative_costs(const PilotEstimate& pilot) {
    const size_t pixels = size_t(pilot.width) * pilot.height;
    if (pilot.sample_cost.size() != pixels) return std::vector<double>(pixels, 1.0);
    std::vector<double> c = box_3x3(pilot.sample_cost, pilot.width, pilot.height);
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / double(pixels);
    for (double& x : c) x = mean > 0 && x > 0 ? x / mean : 1.0;
    return c;
}

// a_p = V_p / (Y_p^2 + 0.01), V and Y over the 3 x 3 neighbourhood: the pixel's relative MSE times its samples.
std::vector<double> relative_variances(const PilotEstimate& pilot) {
    const std::vector<double> v = box_3x3(known_variance(pilot), pilot.width, pilot.height);
    std::vector<double> y(pilot.luminance);
    for (double& l : y) l = std::isfinite(l) ? l : 0.0;
    y = box_3x3(y, pilot.width, pilot.height);
    std::vector<double> a(v.size());
    for (size_t i = 0; i < a.size(); ++i) a[i] = v[i] / (y[i] * y[i] + LUMINANCE_EPSILON);
    return a;
}

// The tiles of ALLOCATION_TILE x ALLOCATION_TILE pixels (smaller at the right and bottom edges), in scanline order.
struct Tiles {
    int columns = 0, rows = 0;
    std::vector<double> a, cost;  // sums over each tile's pixels
    size_t count() const { return a.size(); }
};

size_t tile_of(int x, int y, int columns) { return size_t(y / ALLOCATION_TILE) * columns + size_t(x / ALLOCATION_TILE); }

Tiles make_tiles(const PilotEstimate& pilot, const std::vector<double>& a, const std::vector<double>& cost) {
    Tiles t;
    t.columns = (pilot.width + ALLOCATION_TILE - 1) / ALLOCATION_TILE;
    t.rows = (pilot.height + ALLOCATION_TILE - 1) / ALLOCATION_TILE;
    t.a.assign(size_t(t.columns) * t.rows, 0.0);
    t.cost.assign(t.a.size(), 0.0);
    for (int y = 0; y < pilot.height; ++y)
        for (int x = 0; x < pilot.width; ++x) {
            const size_t p = size_t(y) * pilot.width + x, i = tile_of(x, y, t.columns);
            t.a[i] += a[p];
            t.cost[i] += cost[p];
        }
    return t;
}


// Real-valued counts proportional to w whose cost (sum of cost x count) is `budget`, clamped to [lo, hi] (water
// filling: the clamped pixels keep their bound and the rest share what is left).
std::vector<double> share_out(const std::vector<double>& w, const std::vector<double>& cost, double budget, double lo,
                              double hi) {
    const size_t n = w.size();
    std::vector<double> counts(n, 0.0);
    std::vector<char> fixed(n, 0);
    for (int round = 0; round < 64; ++round) {
        double left = budget, weight = 0;
        for (size_t i = 0; i < n; ++i) {
            if (fixed[i]) left -= counts[i] * cost[i];
            else weight += w[i] * cost[i];
        }
        bool changed = false;
        for (size_t i = 0; i < n; ++i) {
            if (fixed[i]) continue;
            const double c = weight > 0 ? std::max(left, 0.0) * w[i] / weight : lo;
            if (c < lo || c > hi) {
                counts[i] = c < lo ? lo : hi;
                fixed[i] = 1;
                changed = true;
            } else {
                counts[i] = c;
            }
        }
        if (!changed) break;
    }
    return counts;
}

// The nearest power of two, in log terms (LADDER_STEPS_PER_OCTAVE 1).
uint32_t power_of_two_below(double count) {
    uint32_t p = 1;
    while (p <= count / 2 && p < (1u << 31)) p *= 2;
    return p;
}

uint32_t ladder_count(double count) {
    if (count <= 1) return 1;
    const double step = std::round(std::log2(count) * LADDER_STEPS_PER_OCTAVE);
    return uint32_t(std::max(1.0, std::round(std::exp2(step / LADDER_STEPS_PER_OCTAVE))));
}

// The counts on the ladder within [lo, hi] whose cost stays within `budget`: rounded after a common scale (the
// largest that fits), then, while the budget allows, pixels doubled in the order of what they gain per cost (relative
// MSE a / 2n for c n more: w^2 / 2n^2 with a = w^2 c), so that flat regions, which round alike, do not leave half a
// ladder step of the budget unspent.
std::vector<uint32_t> round_to_ladder(const std::vector<double>& counts, const std::vector<double>& w,
                                      const std::vector<double>& cost, double budget, uint32_t lo, uint32_t hi) {
    const size_t pixels = counts.size();
    const auto rounded = [&](double scale, std::vector<uint32_t>& out) {
        double sum = 0;
        for (size_t i = 0; i < pixels; ++i) {
            out[i] = std::clamp(ladder_count(counts[i] * scale), lo, hi);
            sum += out[i] * cost[i];
        }
        return sum;
    };
    std::vector<uint32_t> samples(pixels), trial(pixels);
    double low = 0.25, high = 4.0;
    for (int step = 0; step < 24; ++step) {
        const double mid = std::sqrt(low * high);
        (rounded(mid, trial) <= budget ? low : high) = mid;
    }
    double left = budget - rounded(low, samples);
    std::vector<uint32_t> by_gain(pixels);
    std::iota(by_gain.begin(), by_gain.end(), 0u);
    std::stable_sort(by_gain.begin(), by_gain.end(),
                     [&](uint32_t p, uint32_t q) { return w[p] / samples[p] > w[q] / samples[q]; });
    for (uint32_t p : by_gain) {
        const double more = samples[p] * cost[p];
        if (more <= left && uint64_t(samples[p]) * 2 <= hi) {
            samples[p] *= 2;
            left -= more;
        }
    }
    return samples;
}

}  // namespace

uint64_t SampleAllocation::total_samples() const { return std::accumulate(samples.begin(), samples.end(), uint64_t(0)); }

uint32_t SampleAllocation::tile_samples(size_t tile) const {
    const size_t x = (tile % tile_columns) * ALLOCATION_TILE, y = (tile / tile_columns) * ALLOCATION_TILE;
    return samples[y * width + x];
}

size_t SampleAllocation::tile_pixels(size_t tile) const {
    const int x = int(tile % tile_columns) * ALLOCATION_TILE, y = int(tile / tile_columns) * ALLOCATION_TILE;
    return size_t(std::min(ALLOCATION_TILE, width - x)) * size_t(std::min(ALLOCATION_TILE, height - y));
}

// Tile by tile, each tile's pixels in scanline order: a wave's eight consecutive paths (lavapipe's SIMD group) are
// two rows of four pixels of one tile.
std::vector<uint32_t> SampleAllocation::pixels_of(const std::vector<uint32_t>& tiles) const {
    std::vector<uint32_t> pixels;
    for (uint32_t t : tiles) {
        const int x0 = int(t % tile_columns) * ALLOCATION_TILE, y0 = int(t / tile_columns) * ALLOCATION_TILE;
        for (int y = y0; y < std::min(y0 + ALLOCATION_TILE, height); ++y)
            for (int x = x0; x < std::min(x0 + ALLOCATION_TILE, width); ++x)
                pixels.push_back(uint32_t(size_t(y) * width + x));
    }
    return pixels;
}

void SampleAllocation::order_by_samples() {
    std::vector<uint32_t> tiles(tile_count());
    std::iota(tiles.begin(), tiles.end(), 0u);
    std::stable_sort(tiles.begin(), tiles.end(),
                     [&](uint32_t s, uint32_t t) { return tile_samples(s) > tile_samples(t); });
    order = pixels_of(tiles);
    levels.clear();
    level_pixels.clear();
    for (size_t i = order.size(); i-- > 0;) {  // from the fewest samples up
        const uint32_t n = samples[order[i]];
        if (levels.empty() || levels.back() != n) {
            levels.push_back(n);
            level_pixels.push_back(uint32_t(i + 1));
        }
    }
}

SampleAllocation allocate_samples(const PilotEstimate& pilot, uint64_t total, uint32_t max_spp) {
    const size_t pixels = size_t(pilot.width) * pilot.height;
    if (pixels == 0 || pilot.luminance.size() != pixels || pilot.sample_variance.size() != pixels || max_spp == 0)
        throw std::logic_error("allocate_samples: the pilot does not match its image size");
    const double mean = double(total) / double(pixels);
    const double lo = std::max(double(MIN_ADAPTIVE_SPP), mean / MIN_SHARE_OF_MEAN);
    const double hi = std::max(lo, std::min(double(max_spp), std::ceil(mean * MAX_SHARE_OF_MEAN)));
    // Costs relative to their mean: a budget of `total` even samples is `total` in these units. A tile's pixels share
    // one count n: its relative MSE is A / n and its time C n, A and C its pixels' sums, so tiles are shared out as
    // pixels would be, with weights sqrt(A / C).
    const Tiles tiles = make_tiles(pilot, relative_variances(pilot), relative_costs(pilot));
    std::vector<double> w(tiles.count());
    for (size_t t = 0; t < w.size(); ++t) w[t] = std::sqrt(tiles.a[t] / tiles.cost[t]);
    const std::vector<double> counts = share_out(w, tiles.cost, double(total), std::min(lo, hi), hi);
    const std::vector<uint32_t> tile_counts =
        round_to_ladder(counts, w, tiles.cost, double(total), ladder_count(lo),
                        std::max(power_of_two_below(hi), ladder_count(lo)));
    SampleAllocation a;
    a.width = pilot.width;
    a.height = pilot.height;
    a.tile_columns = tiles.columns;
    a.tile_weights = w;
    a.samples.resize(pixels);
    for (int y = 0; y < pilot.height; ++y)
        for (int x = 0; x < pilot.width; ++x)
            a.samples[size_t(y) * pilot.width + x] = tile_counts[tile_of(x, y, tiles.columns)];
    a.order_by_samples();
    return a;
}

std::vector<float> allocated_variance(const PilotEstimate& pilot, const std::vector<uint32_t>& samples) {
    const std::vector<double> v = known_variance(pilot);
    std::vector<float> out(samples.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = samples[i] > 0 ? float(v[i] / samples[i]) : NAN;
    return out;
}

double predicted_error(const PilotEstimate& pilot, const std::vector<uint32_t>& samples) {
    const std::vector<float> variance = allocated_variance(pilot, samples);
    double sum = 0;
    for (size_t i = 0; i < variance.size(); ++i) {
        const double y = std::isfinite(pilot.luminance[i]) ? pilot.luminance[i] : 0.0;
        sum += variance[i] / (y * y + LUMINANCE_EPSILON);
    }
    return std::sqrt(sum / double(variance.size()));
}

SampleAllocation allocate_for_target(const PilotEstimate& pilot, double target, uint64_t max_total, uint32_t max_spp) {
    const uint64_t pixels = uint64_t(pilot.width) * pilot.height;
    uint64_t lo = pixels, hi = std::max(max_total, pixels);  // totals: below lo nothing changes; hi the limit
    SampleAllocation best = allocate_samples(pilot, hi, max_spp);
    if (predicted_error(pilot, best.samples) > target) return best;
    while (hi - lo > std::max<uint64_t>(1, lo / 64)) {  // to within about 1.5% of the smallest total
        const uint64_t mid = lo + (hi - lo) / 2;
        SampleAllocation a = allocate_samples(pilot, mid, max_spp);
        if (predicted_error(pilot, a.samples) <= target) {
            hi = mid;
            best = std::move(a);
        } else {
            lo = mid;
        }
    }
    return best;
}

}  // namespace fh
