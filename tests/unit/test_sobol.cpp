// The Owen-scrambled Sobol' sampler (shaders/lib/sobol.glsl) on the CPU: its direction numbers against Joe & Kuo's
// construction, the nets its points form (every power-of-two prefix stratifies every pair of a block's dimensions),
// uniform marginals over seeds (unbiased), blocks and pixels that do not correlate, and a lower integration error
// than independent points on a smooth and a discontinuous integrand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "lib/cpp_compat.h"
namespace fh::glsl {
#include "lib/sobol.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;

// Direction numbers of Sobol' dimension `dim` (0: van der Corput; 1-3: Joe & Kuo 2008's first three polynomials,
// (s, a, m) = (1, 0, {1}), (2, 1, {1, 3}), (3, 1, {1, 3, 1})), by the textbook recurrence.
std::vector<uint32_t> direction_numbers(int dim) {
    std::vector<uint32_t> v(32);
    if (dim == 0) {
        for (int i = 0; i < 32; ++i) v[i] = 1u << (31 - i);
        return v;
    }
    const int s[] = {0, 1, 2, 3}, a[] = {0, 0, 1, 1};
    const std::vector<uint32_t> m[] = {{}, {1}, {1, 3}, {1, 3, 1}};
    for (int i = 0; i < s[dim]; ++i) v[i] = m[dim][i] << (31 - i);
    for (int i = s[dim]; i < 32; ++i) {
        uint32_t x = v[i - s[dim]] ^ (v[i - s[dim]] >> s[dim]);
        for (int k = 1; k < s[dim]; ++k) x ^= ((a[dim] >> (s[dim] - 1 - k)) & 1u) * v[i - k];
        v[i] = x;
    }
    return v;
}

TEST(Sobol, MatchesJoeKuoDirectionNumbers) {
    std::vector<uint32_t> v[4];
    for (int d = 0; d < 4; ++d) v[d] = direction_numbers(d);
    std::mt19937 rng(1);
    for (int n = 0; n < 2000; ++n) {
        const uint32_t index = n < 1000 ? uint32_t(n) : uint32_t(rng());
        const uvec4 x = sobol_4d(index);
        for (int d = 0; d < 4; ++d) {
            uint32_t expected = 0;
            for (int bit = 0; bit < 32; ++bit)
                if ((index >> bit) & 1u) expected ^= v[d][bit];
            ASSERT_EQ(x[d], expected) << "index " << index << " dimension " << d;
        }
    }
}

// The quality parameter t of points as a (t, k, 2)-net in dimensions (d0, d1): the smallest t such that every
// elementary interval of volume 2^(t - k) holds exactly 2^t of the 2^k points.
int net_quality(const std::vector<vec4>& points, int k, int d0, int d1) {
    for (int t = 0; t <= k; ++t) {
        bool ok = true;
        for (int a = 0; a <= k - t && ok; ++a) {
            const int b = k - t - a;
            std::vector<int> count(size_t(1) << (k - t), 0);
            for (const vec4& p : points)
                ++count[(size_t(uint32_t(p[d0] * float(1u << a))) << b) | uint32_t(p[d1] * float(1u << b))];
            for (int c : count) ok = ok && c == (1 << t);
        }
        if (ok) return t;
    }
    return k;
}

// The first 2^k points of a block are, in every pair of its dimensions, as good a net as the plain Sobol' points
// (exactly one point per elementary interval in dimensions 0 and 1: a (0, k, 2)-net): Owen scrambling and the index
// shuffle keep that for any seeds and any power-of-two prefix.
TEST(Sobol, PowerOfTwoPrefixesKeepTheNetsOfSobolPoints) {
    const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for (int k : {4, 6, 8}) {
        const uint32_t n = 1u << k;
        std::vector<vec4> plain(n);
        for (uint32_t i = 0; i < n; ++i) plain[i] = vec4(sobol_4d(i) >> 8u) * (1.0f / 16777216.0f);
        for (uint32_t seed : {0u, 7u, 0xdeadbeefu}) {
            std::vector<vec4> points(n);
            for (uint32_t i = 0; i < n; ++i) points[i] = sample_sobol_block(i, seed);
            for (const auto& pair : pairs) {
                const int t = net_quality(plain, k, pair[0], pair[1]);
                if (pair[0] == 0 && pair[1] == 1) EXPECT_EQ(t, 0);
                EXPECT_EQ(net_quality(points, k, pair[0], pair[1]), t)
                    << "seed " << seed << " 2^" << k << " points, dimensions " << pair[0] << "," << pair[1];
            }
        }
    }
}

// Over seeds, any one sample's coordinates are uniform on [0, 1): chi-square over 64 bins, each dimension and index.
TEST(Sobol, EachPointIsUniformOverSeeds) {
    const int bins = 64, seeds = 64000;
    for (uint32_t index : {0u, 1u, 5u, 1000u}) {
        std::vector<int> count[4];
        for (auto& c : count) c.assign(bins, 0);
        for (int s = 0; s < seeds; ++s) {
            const vec4 u = sample_sobol_block(index, sobol_block_seed(uint32_t(s), 3u, 1u));
            for (int d = 0; d < 4; ++d) {
                ASSERT_GE(u[d], 0.0f);
                ASSERT_LT(u[d], 1.0f);
                ++count[d][std::min(int(u[d] * bins), bins - 1)];
            }
        }
        for (int d = 0; d < 4; ++d) {
            double chi2 = 0.0;
            const double expected = double(seeds) / bins;
            for (int c : count[d]) chi2 += (c - expected) * (c - expected) / expected;
            // 63 degrees of freedom: 0.1% critical value 103.4 (4 x 4 tests).
            EXPECT_LT(chi2, 103.4) << "index " << index << " dimension " << d;
        }
    }
}

// Different blocks of one pixel (a vertex's light and BSDF samples, or two depths) and different pixels do not
// correlate: Pearson's r over 4096 samples stays within 4 / sqrt(n).
TEST(Sobol, BlocksAndPixelsDoNotCorrelate) {
    const int n = 4096;
    auto correlation = [&](uint32_t seed_a, int dim_a, uint32_t seed_b, int dim_b) {
        double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
        for (int i = 0; i < n; ++i) {
            const double a = sample_sobol_block(uint32_t(i), seed_a)[dim_a], b = sample_sobol_block(uint32_t(i), seed_b)[dim_b];
            sa += a;
            sb += b;
            sab += a * b;
            saa += a * a;
            sbb += b * b;
        }
        const double cov = sab / n - sa / n * sb / n;
        return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
    };
    for (int d = 0; d < 4; ++d)
        for (int e = 0; e < 4; ++e) {
            EXPECT_LT(std::abs(correlation(sobol_block_seed(10, 0, 1), d, sobol_block_seed(10, 0, 2), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_block_seed(10, 0, 1), d, sobol_block_seed(10, 0, 3), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_block_seed(10, 0, 1), d, sobol_block_seed(11, 0, 1), e)), 4.0 / std::sqrt(n));
            EXPECT_LT(std::abs(correlation(sobol_block_seed(10, 0, 1), d, sobol_block_seed(10, 1, 1), e)), 4.0 / std::sqrt(n));
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
                const vec4 u = sample_sobol_block(uint32_t(i), sobol_block_seed(uint32_t(t), 0u, 0u));
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
