// Adaptive sampling's allocation (render/sample_allocation.h): samples in proportion to sqrt(V / (Y^2 + 0.01)),
// within the floor and the cap, on the power-of-two ladder, the order the waves take, the smallest total that reaches
// a target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/sample_allocation.h"

namespace fh {
namespace {

// A width x height pilot whose left half has per-sample variance `left` and right half `right`, luminance 1.
PilotEstimate halves(int width, int height, double left, double right) {
    PilotEstimate p;
    p.width = width;
    p.height = height;
    p.spp = 16;
    p.luminance.assign(size_t(width) * height, 1.0);
    p.sample_variance.resize(p.luminance.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) p.sample_variance[size_t(y) * width + x] = x < width / 2 ? left : right;
    return p;
}

TEST(SampleAllocation, SamplesFollowTheSquareRootOfTheVariance) {
    const PilotEstimate p = halves(32, 16, 16.0, 1.0);  // sqrt ratio 4
    const SampleAllocation a = allocate_samples(p, 32 * 16 * 40, 65536);
    // Away from the border (the weights are 3 x 3 means), left pixels get 4x the right's, within the ladder's step.
    const double left = a.samples[8 * 32 + 4], right = a.samples[8 * 32 + 28];
    EXPECT_NEAR(left / right, 4.0, 4.0 * 0.2);  // the ladder's steps are powers of two
    EXPECT_NEAR(double(a.total_samples()), 32.0 * 16 * 40, 32.0 * 16 * 40 * 0.06);
}

TEST(SampleAllocation, CostlierPixelsGetFewerSamplesWithinTheSameTime) {
    PilotEstimate p = halves(32, 16, 1.0, 1.0);
    p.sample_cost.resize(p.luminance.size());
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) p.sample_cost[size_t(y) * 32 + x] = x < 16 ? 8.0 : 2.0;
    const uint64_t total = 32 * 16 * 32;
    const SampleAllocation a = allocate_samples(p, total, 65536);
    // n proportional to 1 / sqrt(cost): the right half gets twice the left's (on average: the budget's last tiles are
    // doubled where they gain most).
    double left = 0, right = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) (x < 16 ? left : right) += a.samples[size_t(y) * 32 + x];
    EXPECT_NEAR(right / left, 2.0, 0.5);
    // The time is a uniform render's of `total` samples (mean cost 5), within the ladder's rounding below it.
    double time = 0;
    for (size_t i = 0; i < a.samples.size(); ++i) time += a.samples[i] * p.sample_cost[i];
    EXPECT_LE(time, 5.0 * total * 1.001);
    EXPECT_GT(time, 5.0 * total * 0.7);
}

TEST(SampleAllocation, TheOptimumBeatsUniformSampling) {
    const PilotEstimate p = halves(32, 16, 100.0, 1.0);
    const SampleAllocation a = allocate_samples(p, 32 * 16 * 64, 65536);
    const std::vector<uint32_t> uniform(a.samples.size(), uint32_t(a.total_samples() / a.samples.size()));
    const double adaptive_error = predicted_error(p, a.samples), uniform_error = predicted_error(p, uniform);
    // sqrt(V) 10 and 1: the optimum's relMSE is (mean sqrt V)^2 / N = 30.25 / N against mean V / N = 50.5 / N; powers
    // of two (8 or 16 for 10) cost a few per cent of it.
    EXPECT_LT(adaptive_error, uniform_error * std::sqrt(30.25 / 50.5) * 1.08);
}

TEST(SampleAllocation, FloorAndCap) {
    PilotEstimate p = halves(16, 16, 0.0, 0.0);
    p.sample_variance[5] = 1e6;  // one pixel the pilot saw a firefly in
    const SampleAllocation a = allocate_samples(p, 16 * 16 * 32, 65536);
    for (uint32_t n : a.samples) {
        EXPECT_GE(n, 32u / MIN_SHARE_OF_MEAN);
        EXPECT_LE(n, 32u * MAX_SHARE_OF_MEAN);
    }
    EXPECT_GT(a.samples[5], 32u * 4);
    const SampleAllocation capped = allocate_samples(p, 16 * 16 * 32, 40);
    for (uint32_t n : capped.samples) EXPECT_LE(n, 40u);
}

TEST(SampleAllocation, UnknownVarianceCountsAsTheLargest) {
    PilotEstimate p = halves(16, 16, 1.0, 1.0);
    p.sample_variance[0] = 1e4;
    p.sample_variance[200] = NAN;
    const SampleAllocation a = allocate_samples(p, 16 * 16 * 16, 65536);
    EXPECT_GT(a.samples[200], a.samples[100]);
    EXPECT_TRUE(std::isfinite(predicted_error(p, a.samples)));
}

TEST(SampleAllocation, OrderAndLevelsDescribeTheWaves) {
    PilotEstimate p = halves(24, 12, 1.0, 1.0);
    for (size_t i = 0; i < p.sample_variance.size(); ++i) p.sample_variance[i] = double((i * 7919) % 97);
    const SampleAllocation a = allocate_samples(p, 24 * 12 * 24, 65536);
    ASSERT_EQ(a.order.size(), a.samples.size());
    std::vector<uint32_t> sorted(a.order);
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);  // every pixel once
    for (size_t i = 1; i < a.order.size(); ++i) EXPECT_GE(a.samples[a.order[i - 1]], a.samples[a.order[i]]);
    // A tile's pixels share their count and follow each other, two rows of four first (a SIMD group of eight).
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 24; ++x)
            EXPECT_EQ(a.samples[size_t(y) * 24 + x], a.samples[size_t(y / 4 * 4) * 24 + x / 4 * 4]);
    size_t pixels = 0;
    for (size_t t = 0; t < a.tile_count(); ++t) {
        pixels += a.tile_pixels(t);
        EXPECT_EQ(a.tile_pixels(t), a.pixels_of({uint32_t(t)}).size());
    }
    EXPECT_EQ(pixels, a.samples.size());
    const SampleAllocation edges = allocate_samples(halves(10, 7, 1.0, 4.0), 10 * 7 * 16, 65536);  // partial tiles
    pixels = 0;
    for (size_t t = 0; t < edges.tile_count(); ++t) {
        pixels += edges.tile_pixels(t);
        EXPECT_EQ(edges.tile_pixels(t), edges.pixels_of({uint32_t(t)}).size());
    }
    EXPECT_EQ(pixels, 70u);
    EXPECT_EQ(a.order[1], a.order[0] + 1);
    EXPECT_EQ(a.order[4], a.order[0] + 24);
    ASSERT_EQ(a.levels.size(), a.level_pixels.size());
    EXPECT_EQ(a.level_pixels.front(), a.samples.size());  // the lowest level: every pixel
    for (size_t k = 0; k < a.levels.size(); ++k) {
        if (k > 0) EXPECT_GT(a.levels[k], a.levels[k - 1]);
        uint32_t at_least = 0;
        for (uint32_t n : a.samples) at_least += n >= a.levels[k] ? 1u : 0u;
        EXPECT_EQ(at_least, a.level_pixels[k]);
    }
    // Rendering level by level gives each pixel its count.
    std::vector<uint32_t> rendered(a.samples.size(), 0);
    uint32_t begin = 0;
    for (size_t k = 0; k < a.levels.size(); ++k) {
        for (uint32_t e = 0; e < a.level_pixels[k]; ++e) rendered[a.order[e]] += a.levels[k] - begin;
        begin = a.levels[k];
    }
    EXPECT_EQ(rendered, a.samples);
}

TEST(SampleAllocation, TheTargetGetsTheFewestSamplesThatReachIt) {
    PilotEstimate p = halves(32, 32, 4.0, 0.25);
    for (size_t i = 0; i < p.sample_variance.size(); ++i) p.sample_variance[i] *= 1.0 + double((i * 7919) % 101) / 25.0;
    const double target = 0.05;
    const SampleAllocation a = allocate_for_target(p, target, uint64_t(32) * 32 * 65536, 65536);
    EXPECT_LE(predicted_error(p, a.samples), target);
    const SampleAllocation fewer = allocate_samples(p, a.total_samples() * 9 / 10, 65536);
    EXPECT_GT(predicted_error(p, fewer.samples), target);
    // Out of reach within the limit: the limit's allocation.
    const SampleAllocation limited = allocate_for_target(p, 1e-4, uint64_t(32) * 32 * 8, 65536);
    EXPECT_NEAR(double(limited.total_samples()), 32.0 * 32 * 8, 32.0 * 32 * 8 * 0.06);
}

}  // namespace
}  // namespace fh
