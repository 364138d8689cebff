// How adaptive sampling (`--adaptive`, render/adaptive_render.h) shares samples out among pixels, from what a pilot
// render measured: the allocation that minimises the image's predicted relative error (error_estimate.h
// relative_error) for a number of samples, or the fewest samples predicted to reach a target error.
//
// A pixel's mean over n samples has variance V / n, V the variance of one sample's luminance; the image's relative
// MSE is the mean over pixels of V_p / (n_p (Y_p^2 + 0.01)). A sample of pixel p costs c_p (its paths' vertices and
// shadow rays, as the pilot counted them): for a time sum c_p n_p = T the MSE is smallest when n_p is proportional to
// sqrt(V_p / ((Y_p^2 + 0.01) c_p)) (a Lagrange multiplier). The budget is a time: that of a uniform render of `total`
// samples, so `--adaptive --spp 64` takes about as long as `--spp 64`. The pilot's V, Y and c are noisy (a few batches
// per pixel), so the weights use their means over the pixel's 3 x 3 neighbourhood; every pixel
// gets at least an eighth of the mean (a pixel whose pilot saw no variance may still have some) and at most 16 times
// it and `max_spp`. Counts are powers of two (after a common scale, the largest that keeps the total within the
// budget): Owen-scrambled Sobol' points are best stratified in power-of-two prefixes (measured: a ladder 2^(1/4)
// apart lost Cornell's error to uniform sampling, tests/bench/RESULTS.md), and the waves run a dozen distinct counts.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fh {

// What the pilot measured per film pixel: the luminance of its mean, the variance of one sample's luminance (NaN where
// it could not tell: treated as the noisiest pixel) and the cost of one sample (any unit; empty: the same everywhere).
struct PilotEstimate {
    int width = 0, height = 0;
    uint32_t spp = 0;
    std::vector<double> luminance;
    std::vector<double> sample_variance;
    std::vector<double> sample_cost;
};

// Every pixel gets at least mean / MIN_SHARE_OF_MEAN samples and at least MIN_ADAPTIVE_SPP (four quarters for its own
// variance: render/adaptive_render.h), and at most MAX_SHARE_OF_MEAN x mean (one pixel whose pilot met a rare bright
// path does not take the image's samples).
constexpr uint32_t MIN_SHARE_OF_MEAN = 8;
constexpr uint32_t MIN_ADAPTIVE_SPP = 4;
constexpr uint32_t MAX_SHARE_OF_MEAN = 16;
// Pixels share counts in square tiles of this side, so that a wave's SIMD groups stay compact.
constexpr int ALLOCATION_TILE = 4;

struct SampleAllocation {
    int width = 0, height = 0, tile_columns = 0;
    std::vector<uint32_t> samples;       // per film pixel, a power of two, at least MIN_ADAPTIVE_SPP
    std::vector<double> tile_weights;    // per tile: the pilot's sqrt(A / C), what a sample there is worth
    std::vector<uint32_t> order;         // the film's pixels by samples, most first, tile by tile (scanline order)
    std::vector<uint32_t> levels;        // the distinct counts, ascending
    std::vector<uint32_t> level_pixels;  // level_pixels[k]: pixels with at least levels[k] samples (a prefix of order)
    uint64_t total_samples() const;
    size_t tile_count() const { return tile_weights.size(); }
    uint32_t tile_samples(size_t tile) const;  // the count its pixels share
    size_t tile_pixels(size_t tile) const;     // ALLOCATION_TILE^2, fewer at the right and bottom edges
    // The film's pixels of these tiles, in that order, each tile's in scanline order.
    std::vector<uint32_t> pixels_of(const std::vector<uint32_t>& tiles) const;
    // order, levels and level_pixels again from the samples (after they changed).
    void order_by_samples();
};

// The allocation that costs at most what `total` samples spread evenly cost (within a few per cent below it: the
// counts are powers of two), at most `max_spp` per pixel.
SampleAllocation allocate_samples(const PilotEstimate& pilot, uint64_t total, uint32_t max_spp);

// The variance of each pixel's mean with `samples[p]` samples: the pilot's V_p / n_p (NaN where V_p is).
std::vector<float> allocated_variance(const PilotEstimate& pilot, const std::vector<uint32_t>& samples);

// The image's relative error predicted for these counts, with the pilot's luminance.
double predicted_error(const PilotEstimate& pilot, const std::vector<uint32_t>& samples);

// The cheapest allocation (costing at most what `max_total` even samples cost) predicted to reach `target`; the
// limit's when even that is predicted to fall short.
SampleAllocation allocate_for_target(const PilotEstimate& pilot, double target, uint64_t max_total, uint32_t max_spp);

}  // namespace fh
