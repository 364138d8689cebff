// The per-pixel and per-tile tests of `fredholm compare`; see noise_test.h.
#include "app/compare/noise_test.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/error_estimate.h"

namespace fh {
namespace {

// The continued fraction of the regularized incomplete beta function (modified Lentz), for x < (a + 1) / (a + b + 2).
double beta_continued_fraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1, d = 1 - (a + b) * x / (a + 1);
    d = 1 / (std::fabs(d) < tiny ? tiny : d);
    double h = d;
    for (int m = 1; m <= 300; ++m) {
        for (int step = 0; step < 2; ++step) {
            const double numerator = step == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                               : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
            d = 1 + numerator * d;
            d = 1 / (std::fabs(d) < tiny ? tiny : d);
            c = 1 + numerator / c;
            if (std::fabs(c) < tiny) c = tiny;
            h *= d * c;
            if (step == 1 && std::fabs(d * c - 1) < 1e-15) return h;
        }
    }
    return h;
}

// I_x(a, b).
double regularized_beta(double x, double a, double b) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
    if (x < (a + 1) / (a + b + 2)) return std::exp(log_front) * beta_continued_fraction(a, b, x) / a;
    return 1 - std::exp(log_front) * beta_continued_fraction(b, a, 1 - x) / b;
}

// The x in [0, hi] where the decreasing function f crosses `target`, by bisection on a log scale of the tail.
template <typename Tail>
double upper_quantile(double upper, Tail tail) {
    double lo = 0, hi = 1;
    while (tail(hi) > upper && hi < 1e12) hi *= 2;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (tail(mid) > upper ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace

double normal_upper_quantile(double upper) {
    return upper_quantile(upper, [](double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); });
}

double student_t_upper_tail(double t, double dof) {
    if (t <= 0) return 1 - student_t_upper_tail(-t, dof);
    return 0.5 * regularized_beta(dof / (dof + t * t), dof / 2, 0.5);
}

double student_t_upper_quantile(double upper, double dof) {
    return upper_quantile(upper, [dof](double t) { return student_t_upper_tail(t, dof); });
}

CompareResult compare_images(const NoisyImage& a, const NoisyImage& b, const CompareOptions& o) {
    if (a.image.width != b.image.width || a.image.height != b.image.height)
        throw std::invalid_argument("the images differ in size: " + std::to_string(a.image.width) + "x" +
                                    std::to_string(a.image.height) + " and " + std::to_string(b.image.width) + "x" +
                                    std::to_string(b.image.height));
    CompareResult r;
    const int width = a.image.width, height = a.image.height;
    r.pixels = size_t(width) * height;
    r.with_noise = !a.variance.empty() && !b.variance.empty() && a.degrees_of_freedom > 0 && b.degrees_of_freedom > 0;
    std::vector<double> difference(r.pixels), variance(r.pixels, 0.0);
    double difference_sum = 0, noise_sum = 0;
    for (size_t p = 0; p < r.pixels; ++p) {
        const double ya = pixel_luminance(a.image, p), yb = pixel_luminance(b.image, p), y = 0.5 * (ya + yb);
        difference[p] = ya - yb;
        // A floor far below any noise, so a pixel both renders see without noise (a constant background) tests
        // exactly but rounding does not.
        if (r.with_noise) variance[p] = double(a.variance[p]) + double(b.variance[p]) + 1e-12 * (1 + y * y);
        difference_sum += difference[p] * difference[p] / (y * y + 0.01);
        noise_sum += variance[p] / (y * y + 0.01);
    }
    r.relative_difference = std::sqrt(difference_sum / double(r.pixels));
    r.relative_noise = std::sqrt(noise_sum / double(r.pixels));
    if (!r.with_noise) {
        r.differs = r.relative_difference > o.threshold;
        return r;
    }
    // Bonferroni: half of alpha to the pixels, half to the tiles' two tests each.
    const int tiles_x = (width + o.tile - 1) / o.tile, tiles_y = (height + o.tile - 1) / o.tile;
    r.tiles = size_t(tiles_x) * tiles_y;
    const double dof = std::min(a.degrees_of_freedom, b.degrees_of_freedom);  // Welch's are at least this many
    r.pixel_limit = student_t_upper_quantile(o.alpha / 2 / double(r.pixels) / 2, dof);
    const double tile_alpha = o.alpha / 2 / double(2 * r.tiles);
    r.tile_z_limit = normal_upper_quantile(tile_alpha / 2);
    const double z_one_sided = normal_upper_quantile(tile_alpha);
    r.pixel_z.resize(r.pixels);
    r.pixel_significant.assign(r.pixels, 0);
    for (size_t p = 0; p < r.pixels; ++p) {
        r.pixel_z[p] = float(std::fabs(difference[p]) / std::sqrt(variance[p]));
        r.pixel_significant[p] = r.pixel_z[p] > r.pixel_limit;
        r.significant_pixels += r.pixel_significant[p];
    }
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx) {
            TileVerdict t;
            t.x0 = tx * o.tile, t.y0 = ty * o.tile;
            t.x1 = std::min(width, t.x0 + o.tile), t.y1 = std::min(height, t.y0 + o.tile);
            double d = 0, d2 = 0, v = 0, v2 = 0;
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    const size_t p = size_t(y) * width + x;
                    d += difference[p], d2 += difference[p] * difference[p];
                    v += variance[p], v2 += variance[p] * variance[p];
                }
            t.mean_z = d / std::sqrt(v);
            t.spread = d2 / v;
            // Sum of d^2 over its expectation: about chi-square with m = (sum v)^2 / sum v^2 degrees of freedom over
            // m (Satterthwaite); its upper quantile by Wilson and Hilferty.
            const double m = v * v / v2, c = 2 / (9 * m);
            const double spread_limit = std::pow(1 - c + z_one_sided * std::sqrt(c), 3);
            t.score = std::max(std::fabs(t.mean_z) / r.tile_z_limit, t.spread / spread_limit);
            t.significant = t.score > 1;
            r.significant_tiles += t.significant;
            r.tile_verdicts.push_back(t);
        }
    std::vector<TileVerdict> sorted = r.tile_verdicts;
    std::sort(sorted.begin(), sorted.end(), [](const TileVerdict& x, const TileVerdict& y) { return x.score > y.score; });
    sorted.resize(std::min<size_t>(3, sorted.size()));
    r.worst = sorted;
    r.differs = r.significant_pixels > 0 || r.significant_tiles > 0;
    return r;
}

}  // namespace fh
