// The Owen-scrambled Sobol' sampler (shaders/lib/sampling/sobol.glsl) on the CPU: its two Sobol' dimensions against the
// textbook construction (Joe & Kuo's direction numbers), the nets its points form (every power-of-two prefix is a
// (0, m, 2)-net in 2D and stratified in 1D), uniform marginals over seeds (unbiased), dimensions and pixels that do
// not correlate, and a lower integration error than independent points on a smooth and a discontinuous integrand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/sampling/sobol.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;

// Direction numbers of Sobol' dimension 1 (Joe & Kuo 2008: polynomial x + 1, initial number 1), by the textbook
// recurrence v_i = v_{i-1} ^ (v_{i-1} >> 1).
std::vector<uint32_t> dimension_1_direction_numbers() {
    std::vector<uint32_t> v(32);
    v[0] = 1u << 31;
    for (int i = 1; i < 32; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
    return v;
}

TEST(Sobol, MatchesTheTextbookConstruction) {
    const std::vector<uint32_t> v = dimension_1_direction_numbers();
    std::mt19937 rng(1);
    for (int n = 0; n < 5000; ++n) {
        const uint32_t index = n < 1000 ? uint32_t(n) : uint32_t(rng());
        uint32_t expected = 0, radical_inverse = 0;
        for (int bit = 0; bit < 32; ++bit)
            if ((index >> bit) & 1u) {
                expected ^= v[bit];
                radical_inverse |= 1u << (31 - bit);
            }
        ASSERT_EQ(bitfieldReverse(sobol_dimension_1_reversed(index)), expected) << "index " << index;
        ASSERT_EQ(bitfieldReverse(index), radical_inverse) << "index " << index;
    }
}

// The first 2^k points of a 2D dimension, for any seed, put exactly one point in each elementary interval
// [i / 2^a, (i + 1) / 2^a) x [j / 2^(k - a), (j + 1) / 2^(k - a)): a (0, k, 2)-net; and of a 1D dimension, one point in
// each interval of length 2^-k. The scrambles keep the Sobol' points' nets.
TEST(Sobol, PowerOfTwoPrefixesAreNets) {
    for (uint32_t seed : {0u, 7u, 0xdeadbeefu, 123456789u})
        for (int k : {1, 4, 6, 8, 10}) {
            const uint32_t n = 1u << k;
            std::vector<vec2> points(n);
            std::vector<int> line(n, 0);
            for (uint32_t i = 0; i < n; ++i) {
                points[i] = sample_sobol_2d(i, seed);
                ++line[uint32_t(sample_sobol_1d(i, seed) * float(n))];
            }
            for (int c : line) ASSERT_EQ(c, 1) << "1D, seed " << seed << " 2^" << k << " points";
            for (int a = 0; a <= k; ++a) {
                const int b = k - a;
                std::vector<int> count(n, 0);
                for (const vec2& p : points) ++count[(size_t(uint32_t(p.x * float(1u << a))) << b) | uint32_t(p.y * float(1u << b))];
                for (int c : count)
                    ASSERT_EQ(c, 1) << "2D, seed " << seed << " 2^" << k << " points, intervals 2^-" << a << " x 2^-" << b;
            }
        }
}

// Over seeds, any one sample's coordinates are uniform on [0, 1): chi-square over 64 bins, each coordinate and index.
TEST(Sobol, EachPointIsUniformOverSeeds) {
    const int bins = 64, seeds = 64000;
    for (uint32_t index : {0u, 1u, 5u, 1000u}) {
        std::vector<int> count[3];
        for (auto& c : count) c.assign(bins, 0);
        for (int s = 0; s < seeds; ++s) {
            const uint32_t seed = sobol_seed(uint32_t(s), 3u, 1u);
            const vec2 u2 = sample_sobol_2d(index, seed);
            const float u[3] = {u2.x, u2.y, sample_sobol_1d(index, seed)};
            for (int d = 0; d < 3; ++d) {
                ASSERT_GE(u[d], 0.0f);
                ASSERT_LT(u[d], 1.0f);
                ++count[d][std::min(int(u[d] * bins), bins - 1)];
            }
        }
        for (int d = 0; d < 3; ++d) {
            double chi2 = 0.0;
            const double expected = double(seeds) / bins;
            for (int c : count[d]) chi2 += (c - expected) * (c - expected) / expected;
            // 63 degrees of freedom: 0.1% critical value 103.4 (4 x 3 tests).
            EXPECT_LT(chi2, 103.4) << "index " << index << " coordinate " << d;
        }
    }
}

// Different dimensions of one pixel (a vertex's light and BSDF samples, or two depths) and different pixels or seeds
// do not correlate: Pearson's r over 4096 samples stays within 4 / sqrt(n).
TEST(Sobol, DimensionsAndPixelsDoNotCorrelate) {
    const int n = 4096;
    auto value = [](uint32_t i, uint32_t seed, int coordinate) {
        return coordinate < 2 ? double(sample_sobol_2d(i, seed)[coordinate]) : double(sample_sobol_1d(i, seed));
    };
    auto correlation = [&](uint32_t seed_a, int a_coordinate, uint32_t seed_b, int b_coordinate) {
        double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
        for (int i = 0; i < n; ++i) {
            const double a = value(uint32_t(i), seed_a, a_coordinate), b = value(uint32_t(i), seed_b, b_coordinate);
            sa += a;
            sb += b;
            sab += a * b;
            saa += a * a;
            sbb += b * b;
        }
        const double cov = sab / n - sa / n * sb / n;
        return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
    };
    for (int d = 0; d < 3; ++d)
        for (int e = 0; e < 3; ++e) {
            EXPECT_LT(std::abs(correlation(sobol_seed(10, 0, 4), d, sobol_seed(10, 0, 5), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_seed(10, 0, 4), d, sobol_seed(10, 0, 9), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_seed(10, 0, 4), d, sobol_seed(11, 0, 4), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_seed(10, 0, 4), d, sobol_seed(10, 1, 4), e)), 4.0 / std::sqrt(n));
        }
}

// What the sampler is for: at 256 points, the root-mean-square error over many seeds of a smooth integrand
// (a Gaussian bump) and a discontinuous one (a disk's indicator, a shadow edge) is far below that of independent
// points (RMSE ~ 1 / sqrt(n)); the Sobol' estimates are unbiased (their mean is the integral).
TEST(Sobol, IntegratesWithLessErrorThanIndependentPoints) {
    const int n = 256, trials = 400;
    auto bump = [](float x, float y) { return std::exp(-8.0 * ((x - 0.4) * (x - 0.4) + (y - 0.6) * (y - 0.6))); };
    auto disk = [](float x, float y) { return (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) < 0.16 ? 1.0 : 0.0; };
    // Separable: (int_0^1 exp(-8 (x - 0.4)^2) dx)^2 = (sqrt(pi / 8) / 2 (erf(0.6 sqrt 8) + erf(0.4 sqrt 8)))^2.
    const double erfs = std::erf(0.6 * std::sqrt(8.0)) + std::erf(0.4 * std::sqrt(8.0));
    const double bump_integral = M_PI / 8.0 / 4.0 * erfs * erfs;
    const double disk_integral = M_PI * 0.16;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int f = 0; f < 2; ++f) {
        const double exact = f == 0 ? bump_integral : disk_integral;
        double se_sobol = 0, se_independent = 0, mean_sobol = 0;
        for (int t = 0; t < trials; ++t) {
            double sum_sobol = 0, sum_independent = 0;
            for (int i = 0; i < n; ++i) {
                const vec2 u = sample_sobol_2d(uint32_t(i), sobol_seed(uint32_t(t), 0u, 0u));
                sum_sobol += f == 0 ? bump(u.x, u.y) : disk(u.x, u.y);
                const float x = uniform(rng), y = uniform(rng);
                sum_independent += f == 0 ? bump(x, y) : disk(x, y);
            }
            se_sobol += (sum_sobol / n - exact) * (sum_sobol / n - exact);
            se_independent += (sum_independent / n - exact) * (sum_independent / n - exact);
            mean_sobol += sum_sobol / n / trials;
        }
        const double rmse_sobol = std::sqrt(se_sobol / trials), rmse_independent = std::sqrt(se_independent / trials);
        std::printf("[integrand %s] 256 points: RMSE sobol %.2e, independent %.2e (ratio %.1f)\n", f == 0 ? "bump" : "disk",
                    rmse_sobol, rmse_independent, rmse_independent / rmse_sobol);
        EXPECT_LT(rmse_sobol, rmse_independent / (f == 0 ? 20.0 : 3.0));
        EXPECT_NEAR(mean_sobol, exact, 4.0 * rmse_sobol / std::sqrt(double(trials)) + 1e-6);
    }
}

}  // namespace
