// Per-pixel two-sample test between two sets of independent batch renders (Welch 1947), with the Student t
// tail from the regularised incomplete beta function (continued fraction, Lentz's method).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "image_compare.h"

namespace fh {
namespace {

// Continued fraction of the incomplete beta function (Numerical Recipes 3rd ed., sec. 6.4).
double incomplete_beta_fraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m <= 500; ++m) {
        const double m2 = 2.0 * m;
        double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
        d = 1.0 + aa * d;
        c = 1.0 + aa / c;
        if (std::abs(d) < tiny) d = tiny;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
        d = 1.0 + aa * d;
        c = 1.0 + aa / c;
        if (std::abs(d) < tiny) d = tiny;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double step = d * c;
        h *= step;
        if (std::abs(step - 1.0) < 1e-15) break;
    }
    return h;
}

struct PixelMoments {
    double mean = 0, variance = 0;  // of the batch means (unbiased variance)
};

PixelMoments moments(const std::vector<Image>& batches, size_t index) {
    PixelMoments m;
    const double n = double(batches.size());
    for (const Image& b : batches) m.mean += b.rgb[index];
    m.mean /= n;
    for (const Image& b : batches) m.variance += (b.rgb[index] - m.mean) * (b.rgb[index] - m.mean);
    m.variance /= n - 1.0;
    return m;
}

}  // namespace

double regularized_incomplete_beta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                                  b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * incomplete_beta_fraction(a, b, x) / a;
    return 1.0 - front * incomplete_beta_fraction(b, a, 1.0 - x) / b;
}

double student_t_two_sided_p(double t, double dof) {
    if (!std::isfinite(t)) return 0.0;
    return regularized_incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

DistributionResult compare_distributions(const std::vector<Image>& test, const std::vector<Image>& reference,
                                         double alpha) {
    DistributionResult r;
    if (test.size() < 2 || reference.size() < 2) {
        r.failures.push_back("need at least 2 batches on each side");
        return r;
    }
    for (const std::vector<Image>* side : {&test, &reference})
        for (const Image& b : *side)
            if (b.width != test[0].width || b.height != test[0].height) {
                r.failures.push_back("batch sizes differ");
                return r;
            }
    const size_t values = test[0].rgb.size();
    r.tests = values;
    r.p_critical = alpha / double(std::max<size_t>(values, 1));  // Bonferroni over pixels x channels
    r.difference = test[0];
    r.worst_p = 1.0;
    for (size_t i = 0; i < values; ++i) {
        const PixelMoments a = moments(test, i), b = moments(reference, i);
        r.difference.rgb[i] = float(a.mean - b.mean);
        const double va = a.variance / double(test.size()), vb = b.variance / double(reference.size());
        double p = 1.0;
        if (va + vb > 0.0) {
            const double t = (a.mean - b.mean) / std::sqrt(va + vb);
            // Welch-Satterthwaite degrees of freedom.
            const double dof = (va + vb) * (va + vb) /
                               (va * va / double(test.size() - 1) + vb * vb / double(reference.size() - 1));
            p = student_t_two_sided_p(t, dof);
        } else if (a.mean != b.mean) {
            p = 0.0;  // both noiseless yet different
        }
        if (p < r.worst_p) {
            r.worst_p = p;
            r.worst_index = i;
            r.worst_test_mean = a.mean;
            r.worst_reference_mean = b.mean;
        }
        if (p < r.p_critical) ++r.failing;
    }
    const int width = test[0].width;
    const size_t pixel = r.worst_index / 3;
    char line[320];
    std::snprintf(line, sizeof line,
                  "%zu batches vs %zu, %zu pixel-channels: %zu below p %.3g (Bonferroni, alpha %.3g); worst p %.3g at "
                  "(%zu, %zu) channel %zu: %.6g vs %.6g",
                  test.size(), reference.size(), values, r.failing, r.p_critical, alpha, r.worst_p,
                  pixel % size_t(width), pixel / size_t(width), r.worst_index % 3, r.worst_test_mean,
                  r.worst_reference_mean);
    r.summary = line;
    if (r.failing > 0)
        r.failures.push_back(std::to_string(r.failing) + " pixel-channel(s) differ significantly in distribution");
    return r;
}

}  // namespace fh
