// Per-image error metrics, variance/bias estimates from progressive films, log-log fits and target times.
#include "app/converge/converge_metrics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>

namespace fh {
namespace {

bool same_shape(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size();
}

// Mean and standard error of per-pixel values (channels averaged first: they are strongly correlated).
struct MeanAndError {
    double sum = 0, sum_sq = 0;
    uint64_t n = 0;
    void add(double v) { sum += v, sum_sq += v * v, ++n; }
    double mean() const { return n ? sum / double(n) : 0.0; }
    double stderr_of_mean() const {
        if (n < 2) return 0.0;
        double m = mean();
        return std::sqrt(std::max(0.0, (sum_sq / double(n) - m * m) / double(n - 1)));
    }
};

double variance_factor(const EarlierImage& e) {
    assert(e.spp > 0 && e.spp_now > e.spp);
    return double(e.spp) / double(e.spp_now - e.spp);
}

}  // namespace

double estimate_variance(const Image& x, const EarlierImage& earlier) {
    if (!earlier.image) return 0.0;
    const double k = variance_factor(earlier);
    double sum = 0;
    uint64_t n = 0;
    for (size_t i = 0; i < x.rgb.size(); ++i) {
        double d = double(earlier.image->rgb[i]) - double(x.rgb[i]);
        if (!std::isfinite(d)) continue;
        sum += d * d * k;
        ++n;
    }
    return n ? sum / double(n) : 0.0;
}

ImageErrors measure_errors(const Image& x, const Image& reference, const EarlierImage& earlier,
                           const EarlierImage& reference_earlier) {
    if (!same_shape(x, reference)) throw std::invalid_argument("measure_errors: image and reference differ in size");
    const bool with_var = earlier.image && same_shape(*earlier.image, x);
    const bool with_ref_var = reference_earlier.image && same_shape(*reference_earlier.image, x);
    const double k = with_var ? variance_factor(earlier) : 0.0;
    const double k_ref = with_ref_var ? variance_factor(reference_earlier) : 0.0;

    ImageErrors e;
    double sum_sq = 0, sum_rel = 0, sum_abs = 0, sum_var = 0, sum_rel_var = 0;
    uint64_t n = 0;
    MeanAndError bias, rel_bias;
    const size_t pixels = size_t(x.width) * size_t(x.height);
    for (size_t p = 0; p < pixels; ++p) {
        double pixel_bias = 0, pixel_rel_bias = 0;
        int channels = 0;
        for (size_t c = 0; c < 3; ++c) {
            const size_t i = 3 * p + c;
            const double v = x.rgb[i], r = reference.rgb[i];
            const double h = with_var ? double(earlier.image->rgb[i]) : v;
            const double rh = with_ref_var ? double(reference_earlier.image->rgb[i]) : r;
            if (!std::isfinite(v) || !std::isfinite(r) || !std::isfinite(h) || !std::isfinite(rh)) {
                ++e.nonfinite;
                continue;
            }
            const double d2 = (v - r) * (v - r), w = 1.0 / (r * r + REL_EPS);
            const double var = (h - v) * (h - v) * k, ref_var = (rh - r) * (rh - r) * k_ref;
            sum_sq += d2;
            sum_rel += d2 * w;
            sum_abs += std::abs(v - r) / (std::abs(r) + REL_EPS);
            sum_var += var;
            sum_rel_var += var * w;
            pixel_bias += d2 - var - ref_var;
            pixel_rel_bias += (d2 - var - ref_var) * w;
            ++channels, ++n;
        }
        if (channels) bias.add(pixel_bias / channels), rel_bias.add(pixel_rel_bias / channels);
    }
    if (n == 0) return e;
    e.mse = sum_sq / double(n);
    e.relmse = sum_rel / double(n);
    e.mape = sum_abs / double(n);
    if (with_var) {
        e.has_variance = true;
        e.variance = sum_var / double(n);
        e.rel_variance = sum_rel_var / double(n);
        e.bias2 = bias.mean();
        e.bias2_stderr = bias.stderr_of_mean();
        e.rel_bias2 = rel_bias.mean();
        e.rel_bias2_stderr = rel_bias.stderr_of_mean();
    }
    return e;
}

ImageErrors measure_two_seed_errors(const Image& a, const Image& b) {
    if (!same_shape(a, b)) throw std::invalid_argument("measure_two_seed_errors: images differ in size");
    ImageErrors e;
    double sum_sq = 0, sum_rel = 0, sum_abs = 0;
    uint64_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double u = a.rgb[i], v = b.rgb[i];
        if (!std::isfinite(u) || !std::isfinite(v)) {
            ++e.nonfinite;
            continue;
        }
        const double m = 0.5 * (u + v), d2 = (u - v) * (u - v);
        sum_sq += 0.5 * d2;
        sum_rel += 0.5 * d2 / (m * m + REL_EPS);
        sum_abs += std::abs(u - v) / std::sqrt(2.0) / (std::abs(m) + REL_EPS);
        ++n;
    }
    if (n == 0) return e;
    e.mse = sum_sq / double(n);
    e.relmse = sum_rel / double(n);
    e.mape = sum_abs / double(n);
    return e;
}

double fit_loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
        if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, ++n;
    }
    const double den = n * sxx - sx * sx;
    if (n < 2 || !(std::abs(den) > 1e-12)) return std::nan("");
    return (n * sxy - sx * sy) / den;
}

TargetTime time_to_reach(const std::vector<ConvergeStep>& steps, double rel_floor, bool floor_significant,
                         double target) {
    TargetTime t;
    for (size_t i = 0; i < steps.size(); ++i) {
        if (!(steps[i].errors.relmse <= target)) continue;
        t.kind = TargetTime::reached;
        t.seconds = steps[i].seconds;
        if (i > 0) {  // the straight line between steps i-1 and i in log(seconds), log(relMSE)
            const double x0 = std::log(steps[i - 1].seconds), x1 = std::log(steps[i].seconds);
            const double y0 = std::log(steps[i - 1].errors.relmse), y1 = std::log(steps[i].errors.relmse);
            if (y0 > y1 && std::isfinite(x0)) t.seconds = std::exp(x0 + (x1 - x0) * (std::log(target) - y0) / (y1 - y0));
        }
        return t;
    }
    if (steps.empty() || (floor_significant && rel_floor >= target)) return t;  // never
    const ConvergeStep& last = steps.back();
    const double floor = floor_significant ? rel_floor : 0.0;
    t.kind = TargetTime::extrapolated;
    t.seconds = last.seconds * (last.errors.relmse - floor) / (target - floor);
    return t;
}

CurveSummary summarize_curve(const ConvergeCurve& curve, uint32_t width, uint32_t height) {
    CurveSummary s;
    if (curve.steps.empty()) return s;
    std::vector<double> spp, seconds, mse, relmse;
    const size_t first = curve.steps.size() > FIT_STEPS ? curve.steps.size() - FIT_STEPS : 0;
    for (size_t i = first; i < curve.steps.size(); ++i) {
        const ConvergeStep& st = curve.steps[i];
        spp.push_back(st.spp), seconds.push_back(st.seconds);
        mse.push_back(st.errors.mse), relmse.push_back(st.errors.relmse);
    }
    s.fit_steps = uint32_t(spp.size());
    s.slope_mse_spp = fit_loglog_slope(spp, mse);
    s.slope_mse_seconds = fit_loglog_slope(seconds, mse);
    s.slope_relmse_seconds = fit_loglog_slope(seconds, relmse);
    const ConvergeStep& last = curve.steps.back();
    if (last.seconds > 0) {
        s.samples_per_second = double(width) * height * last.spp / last.seconds;
        if (last.errors.mse > 0) s.efficiency = 1.0 / (last.errors.mse * last.seconds);
    }
    s.has_bias = last.errors.has_variance;
    if (s.has_bias) {
        s.bias2 = last.errors.bias2;
        s.bias2_stderr = last.errors.bias2_stderr;
        s.rel_floor = last.errors.rel_bias2;
        s.rel_floor_stderr = last.errors.rel_bias2_stderr;
        s.floor_significant = s.rel_floor > 3.0 * s.rel_floor_stderr && s.rel_floor > 0;
    }
    for (int k = 0; k < 3; ++k)
        s.time_to[k] = time_to_reach(curve.steps, s.rel_floor, s.floor_significant, TARGET_RELMSE[k]);
    return s;
}

}  // namespace fh
