// Statistical comparison of a render against a reference: image means plus per-tile relative size and z-score.
#include "image_compare.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "format_text.h"

namespace fh {

namespace {

constexpr const char* CHANNEL_NAMES[4] = {"R", "G", "B", "luminance"};
constexpr double INF = std::numeric_limits<double>::infinity();

// |a - b| / |b|, with 0/0 = 0 and x/0 = infinity, so an all-black reference still compares sensibly.
double relative_difference(double a, double b) {
    const double d = std::abs(a - b);
    if (d == 0) return 0;
    return std::abs(b) > 0 ? d / std::abs(b) : INF;
}

struct Tile {
    int x0, y0, x1, y1;  // [x0, x1) x [y0, y1)
};

// Tile means of test and reference for one channel, and the standard error of their difference estimated
// from the spread of the per-pixel residual inside the tile (Welford would be overkill: two passes).
void measure_tile(const Image& test, const Image& reference, const Tile& tile, int c, double floor,
                  BlockStat& stat) {
    const double n = double(tile.x1 - tile.x0) * double(tile.y1 - tile.y0);
    double sum_t = 0, sum_r = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            const std::size_t i = (std::size_t(y) * test.width + x) * 3 + c;
            sum_t += test.rgb[i];
            sum_r += reference.rgb[i];
        }
    const double t = sum_t / n, r = sum_r / n, d = t - r;
    double sum_sq = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            const std::size_t i = (std::size_t(y) * test.width + x) * 3 + c;
            const double e = (double(test.rgb[i]) - double(reference.rgb[i])) - d;
            sum_sq += e * e;
        }
    // One pixel carries no estimate of its own noise: such a tile is never called significant.
    const double se = n > 1 ? std::sqrt(sum_sq / (n - 1) / n) : INF;
    const double denominator = std::max(r, floor);
    stat.x = tile.x0;
    stat.y = tile.y0;
    stat.channel = c;
    stat.test_mean = t;
    stat.reference_mean = r;
    stat.rel = d == 0 ? 0 : (denominator > 0 ? std::abs(d) / denominator : INF);
    stat.z = d == 0 ? 0 : (se > 0 ? d / se : std::copysign(INF, d));
}

std::string describe(const BlockStat& s) {
    return format_text("tile (%d,%d) %s test %.6g ref %.6g rel %.3f%% z %.2f", s.x, s.y, CHANNEL_NAMES[s.channel],
                       s.test_mean, s.reference_mean, 100 * s.rel, s.z);
}

}  // namespace

double luminance(float r, float g, float b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

double normal_upper_quantile(double upper_tail) {
    // Bisection on the survival function 0.5 erfc(z / sqrt 2): monotone, and erfc stays accurate far into the
    // tail (1e-300), so no rational approximation is needed; 200 halvings of [-40, 40] reach double precision.
    double lo = -40, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(mid / std::sqrt(2.0)) > upper_tail ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double bonferroni_z_threshold(double alpha, std::size_t tests) {
    return normal_upper_quantile(alpha / (2.0 * double(std::max<std::size_t>(tests, 1))));
}

ReferenceResult compare_to_reference(const Image& test, const Image& reference, const ReferenceOptions& options) {
    ReferenceResult result;
    if (test.width != reference.width || test.height != reference.height) {
        result.failures.push_back(format_text("size: test is %d x %d, reference is %d x %d", test.width, test.height,
                                              reference.width, reference.height));
        result.summary = result.failures.back();
        return result;
    }
    const std::size_t values = test.rgb.size();

    // Non-finite values would turn every statistic into NaN, and NaN compares false: catch them explicitly.
    std::size_t non_finite = 0, first_bad = 0;
    for (std::size_t i = values; i-- > 0;)
        if (!std::isfinite(test.rgb[i])) ++non_finite, first_bad = i;
    if (non_finite)
        result.failures.push_back(format_text("finite: %zu test values are NaN or infinite (first at pixel %zu,%zu)",
                                              non_finite, first_bad / 3 % test.width, first_bad / 3 / test.width));

    // Mean test.
    std::array<double, 3> sum_t{}, sum_r{};
    for (std::size_t i = 0; i < values; ++i) sum_t[i % 3] += test.rgb[i], sum_r[i % 3] += reference.rgb[i];
    const double pixels = double(values / 3);
    for (int c = 0; c < 3; ++c) result.test_mean[c] = sum_t[c] / pixels, result.reference_mean[c] = sum_r[c] / pixels;
    result.test_mean[3] = luminance(result.test_mean[0], result.test_mean[1], result.test_mean[2]);
    result.reference_mean[3] = luminance(result.reference_mean[0], result.reference_mean[1], result.reference_mean[2]);
    std::string mean_failures;
    for (int c = 0; c < 4; ++c) {
        result.mean_rel[c] = relative_difference(result.test_mean[c], result.reference_mean[c]);
        if (!(result.mean_rel[c] <= options.max_mean_rel))
            mean_failures += format_text(" %s %+.3f%% (test %.6g ref %.6g)", CHANNEL_NAMES[c],
                                         100 * (result.test_mean[c] - result.reference_mean[c]) /
                                             std::abs(result.reference_mean[c]),
                                         result.test_mean[c], result.reference_mean[c]);
    }
    if (!mean_failures.empty())
        result.failures.push_back(format_text("mean: relative difference over %.3f%%:", 100 * options.max_mean_rel) +
                                  mean_failures);

    // Block test.
    const int block = std::max(options.block, 1);
    const int tiles_x = (test.width + block - 1) / block, tiles_y = (test.height + block - 1) / block;
    result.tiles = tiles_x * tiles_y;
    result.z_critical = bonferroni_z_threshold(options.alpha, std::size_t(result.tiles) * 3);
    result.z_image = Image{test.width, test.height, std::vector<float>(values)};
    BlockStat worst_failing;
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            const Tile tile{tx * block, ty * block, std::min((tx + 1) * block, test.width),
                            std::min((ty + 1) * block, test.height)};
            for (int c = 0; c < 3; ++c) {
                BlockStat s;
                measure_tile(test, reference, tile, c, 1e-2 * result.reference_mean[c], s);
                const bool big = !(s.rel <= options.max_block_rel);
                const bool significant = !(std::abs(s.z) <= result.z_critical);
                result.over_rel += big;
                result.over_z += significant;
                if (big && significant && !(s.rel <= worst_failing.rel)) worst_failing = s;
                result.failing_blocks += big && significant;
                if (!(s.rel <= result.worst_rel.rel)) result.worst_rel = s;
                if (!(std::abs(s.z) <= std::abs(result.worst_z.z))) result.worst_z = s;
                for (int y = tile.y0; y < tile.y1; ++y)
                    for (int x = tile.x0; x < tile.x1; ++x)
                        result.z_image.rgb[(std::size_t(y) * test.width + x) * 3 + c] = float(s.z);
            }
        }
    if (result.failing_blocks)
        result.failures.push_back(format_text("blocks: %d of %d tile-channels (%dx%d) differ by more than %.2f%% and "
                                              "significantly (|z| > %.2f); worst: ",
                                              result.failing_blocks, 3 * result.tiles, block, block,
                                              100 * options.max_block_rel, result.z_critical) +
                                  describe(worst_failing));

    result.difference = Image{test.width, test.height, std::vector<float>(values)};
    for (std::size_t i = 0; i < values; ++i) result.difference.rgb[i] = test.rgb[i] - reference.rgb[i];

    result.summary = format_text("%s: mean rel R %.4f%% G %.4f%% B %.4f%% lum %.4f%% (max %.3f%%); %d tiles %dx%d: "
                                 "%d over rel %.2f%%, %d over |z| %.2f, %d failing; worst rel ",
                                 result.passed() ? "PASS" : "FAIL", 100 * result.mean_rel[0], 100 * result.mean_rel[1],
                                 100 * result.mean_rel[2], 100 * result.mean_rel[3], 100 * options.max_mean_rel,
                                 result.tiles, block, block, result.over_rel, 100 * options.max_block_rel,
                                 result.over_z, result.z_critical, result.failing_blocks) +
                     describe(result.worst_rel) + "; worst |z| " + describe(result.worst_z);
    return result;
}

}  // namespace fh
