// The non-statistical image checks: furnace constancy, bit-identity and finiteness.
#include <bit>
#include <cmath>
#include <cstdint>

#include "format_text.h"
#include "image_compare.h"

namespace fh {

namespace {

constexpr const char* CHANNEL_NAMES[3] = {"R", "G", "B"};

std::string size_mismatch(const Image& a, const Image& b) {
    return format_text("size: test is %d x %d, other is %d x %d", a.width, a.height, b.width, b.height);
}

}  // namespace

CheckResult check_constant(const Image& test, double value, double tolerance, int ignore_border, double mean_tolerance) {
    return check_constant(test, std::array<double, 3>{value, value, value}, tolerance, ignore_border, mean_tolerance);
}

CheckResult check_constant(const Image& test, const std::array<double, 3>& value, double tolerance, int ignore_border,
                           double mean_tolerance) {
    CheckResult result;
    if (mean_tolerance < 0) mean_tolerance = tolerance / 10;
    // Relative tolerance, absolute around zero; a grey constant is printed as one number.
    auto scale_of = [&](int c) { return value[c] != 0 ? std::abs(value[c]) : 1.0; };
    const bool grey = value[0] == value[1] && value[1] == value[2];
    const std::string expected = grey ? format_text("%g", value[0]) : format_text("%g,%g,%g", value[0], value[1], value[2]);
    const int x0 = ignore_border, x1 = test.width - ignore_border;
    const int y0 = ignore_border, y1 = test.height - ignore_border;
    if (x0 < 0 || x1 <= x0 || y1 <= y0) {
        result.failures.push_back(format_text("border: ignoring %d pixels per side leaves nothing of a %d x %d image",
                                              ignore_border, test.width, test.height));
        result.summary = result.failures.back();
        return result;
    }
    double sum[3] = {0, 0, 0}, worst = -1;
    int worst_x = 0, worst_y = 0, worst_c = 0;
    std::size_t bad = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) {
                const double v = test.rgb[(std::size_t(y) * test.width + x) * 3 + c];
                const double deviation = std::abs(v - value[c]) / scale_of(c);
                sum[c] += v;
                bad += !(deviation <= tolerance);
                if (!(deviation <= worst)) worst = deviation, worst_x = x, worst_y = y, worst_c = c;
            }
    const std::size_t at_worst = (std::size_t(worst_y) * test.width + worst_x) * 3 + worst_c;
    const char* sense = value[0] != 0 || value[1] != 0 || value[2] != 0 ? "relative" : "absolute";
    if (bad)
        result.failures.push_back(format_text("pixels: %zu values deviate from %s by more than %g (%s); worst at (%d,%d) "
                                              "%s = %.6g (off by %.3g)",
                                              bad, expected.c_str(), tolerance, sense, worst_x, worst_y, CHANNEL_NAMES[worst_c],
                                              double(test.rgb[at_worst]), worst));

    const double pixels = double(x1 - x0) * double(y1 - y0);
    std::string mean_text, mean_failures;
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / pixels, deviation = std::abs(mean - value[c]) / scale_of(c);
        mean_text += format_text(" %s %.6g", CHANNEL_NAMES[c], mean);
        if (!(deviation <= mean_tolerance))
            mean_failures += format_text(" %s %.6g (off by %.3g)", CHANNEL_NAMES[c], mean, deviation);
    }
    if (!mean_failures.empty())
        result.failures.push_back(format_text("mean: deviates from %s by more than %g (%s):", expected.c_str(), mean_tolerance,
                                              sense) + mean_failures);

    result.difference = Image{test.width, test.height, std::vector<float>(test.rgb.size())};
    for (std::size_t i = 0; i < test.rgb.size(); ++i) result.difference.rgb[i] = float(test.rgb[i] - value[i % 3]);
    result.summary = format_text("%s: constant %s over %d x %d pixels: %zu values off by more than %.3g, worst %.3g "
                                 "at (%d,%d) %s; means",
                                 result.passed() ? "PASS" : "FAIL", expected.c_str(), x1 - x0, y1 - y0, bad, tolerance, worst,
                                 worst_x, worst_y, CHANNEL_NAMES[worst_c]) +
                     mean_text;
    return result;
}

CheckResult check_identical(const Image& test, const Image& other) {
    CheckResult result;
    if (test.width != other.width || test.height != other.height) {
        result.failures.push_back(size_mismatch(test, other));
        result.summary = result.failures.back();
        return result;
    }
    std::size_t differing = 0, first = 0;
    for (std::size_t i = test.rgb.size(); i-- > 0;)
        if (std::bit_cast<std::uint32_t>(test.rgb[i]) != std::bit_cast<std::uint32_t>(other.rgb[i]))
            ++differing, first = i;
    if (differing) {
        const std::size_t pixel = first / 3;
        result.failures.push_back(format_text(
            "identical: %zu of %zu values differ; first at pixel (%zu,%zu) %s: %.9g (0x%08x) vs %.9g (0x%08x)",
            differing, test.rgb.size(), pixel % test.width, pixel / test.width, CHANNEL_NAMES[first % 3],
            double(test.rgb[first]), std::bit_cast<std::uint32_t>(test.rgb[first]), double(other.rgb[first]),
            std::bit_cast<std::uint32_t>(other.rgb[first])));
    }
    result.difference = Image{test.width, test.height, std::vector<float>(test.rgb.size())};
    for (std::size_t i = 0; i < test.rgb.size(); ++i) result.difference.rgb[i] = test.rgb[i] - other.rgb[i];
    result.summary = format_text("%s: %zu of %zu values differ (%d x %d pixels)", differing ? "FAIL" : "PASS", differing,
                                 test.rgb.size(), test.width, test.height);
    return result;
}

CheckResult check_finite(const Image& test) {
    CheckResult result;
    result.difference = Image{test.width, test.height, std::vector<float>(test.rgb.size())};
    std::size_t bad = 0, first = 0;
    for (std::size_t i = test.rgb.size(); i-- > 0;)
        if (!std::isfinite(test.rgb[i])) ++bad, first = i, result.difference.rgb[i] = 1;
    if (bad)
        result.failures.push_back(format_text("finite: %zu of %zu values are NaN or infinite; first at pixel (%zu,%zu) "
                                              "%s = %g",
                                              bad, test.rgb.size(), first / 3 % test.width, first / 3 / test.width,
                                              CHANNEL_NAMES[first % 3], double(test.rgb[first])));
    result.summary = format_text("%s: %zu of %zu values NaN or infinite", bad ? "FAIL" : "PASS", bad, test.rgb.size());
    return result;
}

CheckResult check_elongation(const Image& test, char axis, double min_ratio) {
    CheckResult result;
    double weight = 0.0, mx = 0.0, my = 0.0, mxx = 0.0, myy = 0.0;
    for (int y = 0; y < test.height; ++y)
        for (int x = 0; x < test.width; ++x) {
            const float* p = &test.rgb[(std::size_t(y) * test.width + x) * 3];
            const double w = luminance(p[0], p[1], p[2]);
            if (!(w > 0.0) || !std::isfinite(w)) continue;
            weight += w;
            mx += w * x;
            my += w * y;
            mxx += w * double(x) * x;
            myy += w * double(y) * y;
        }
    if (!(weight > 0.0)) {
        result.failures.push_back("elongation: the image is black");
        result.summary = result.failures.back();
        return result;
    }
    mx /= weight;
    my /= weight;
    const double var_x = mxx / weight - mx * mx, var_y = myy / weight - my * my;
    const double along = axis == 'x' ? var_x : var_y, across = axis == 'x' ? var_y : var_x;
    const double ratio = along / std::max(across, 1e-30);
    if (!(ratio >= min_ratio))
        result.failures.push_back(format_text("elongation: the light's spread along %c is %.3g times that across it "
                                              "(variances %.4g and %.4g px^2), below %g",
                                              axis, ratio, along, across, min_ratio));
    result.summary = format_text("spread along %c / across: %.3g (variances %.4g and %.4g px^2; at least %g)", axis,
                                 ratio, along, across, min_ratio);
    return result;
}

namespace {

// Luminance-weighted mean squared distance of the pixels from their centroid, px^2 (pixel centres); -1: black.
double second_moment(const Image& image) {
    double weight = 0.0, mx = 0.0, my = 0.0, m2 = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const float* p = &image.rgb[(std::size_t(y) * image.width + x) * 3];
            const double w = luminance(p[0], p[1], p[2]);
            if (!(w > 0.0) || !std::isfinite(w)) continue;
            weight += w;
            mx += w * x;
            my += w * y;
            m2 += w * (double(x) * x + double(y) * y);
        }
    if (!(weight > 0.0)) return -1.0;
    mx /= weight;
    my /= weight;
    return m2 / weight - mx * mx - my * my;
}

}  // namespace

CheckResult check_blur_diameter(const Image& test, const Image& sharp, double expected_px, double tolerance_px) {
    CheckResult result;
    const std::string mismatch =
        test.width != sharp.width || test.height != sharp.height ? size_mismatch(test, sharp) : std::string();
    const double m_test = second_moment(test), m_sharp = second_moment(sharp);
    if (!mismatch.empty() || m_test < 0.0 || m_sharp < 0.0) {
        result.failures.push_back(!mismatch.empty() ? mismatch : "blur: an image is black");
        result.summary = result.failures.back();
        return result;
    }
    const double diameter = std::sqrt(std::max(8.0 * (m_test - m_sharp), 0.0));
    if (!(std::abs(diameter - expected_px) <= tolerance_px))
        result.failures.push_back(format_text("blur: the light spreads over a disk of %.3f px, expected %.3f +- %.3f",
                                              diameter, expected_px, tolerance_px));
    result.summary = format_text("blur disk %.3f px (expected %.3f +- %.3f; second moments %.3f and %.3f px^2)", diameter,
                                 expected_px, tolerance_px, m_test, m_sharp);
    return result;
}

CheckResult check_smear_profile(const Image& test, double left_px, double width_px, double travel_px, int row_begin,
                                int row_end, double tolerance) {
    CheckResult result;
    if (!(row_begin >= 0 && row_begin < row_end && row_end <= test.height)) {
        result.failures.push_back(format_text("smear: rows [%d, %d) lie outside the %d-row image", row_begin, row_end,
                                              test.height));
        result.summary = result.failures.back();
        return result;
    }
    // The covered time at image x: the bar covers x while left + travel s <= x <= left + travel s + width, s in [0, 1].
    auto covered = [&](double x) {
        if (travel_px <= 0.0) return x >= left_px && x <= left_px + width_px ? 1.0 : 0.0;
        const double s0 = std::max((x - width_px - left_px) / travel_px, 0.0), s1 = std::min((x - left_px) / travel_px, 1.0);
        return std::max(s1 - s0, 0.0);
    };
    double worst = 0.0;
    int worst_column = 0;
    double worst_expected = 0.0, worst_measured = 0.0;
    for (int x = 0; x < test.width; ++x) {
        constexpr int STEPS = 256;  // midpoint rule over the pixel: exact but at the trapezoid's four corners
        double expected = 0.0;
        for (int k = 0; k < STEPS; ++k) expected += covered(x + (k + 0.5) / STEPS);
        expected /= STEPS;
        double measured = 0.0;
        for (int y = row_begin; y < row_end; ++y) {
            const float* p = &test.rgb[(std::size_t(y) * test.width + x) * 3];
            measured += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
        measured /= row_end - row_begin;
        const double error = std::abs(measured - expected);
        if (!(error <= worst)) {
            worst = error;
            worst_column = x;
            worst_expected = expected;
            worst_measured = measured;
        }
    }
    if (!(worst <= tolerance))
        result.failures.push_back(format_text("smear: column %d reads %.4f, the moving bar's profile %.4f (off by %.4f, "
                                              "tolerance %.4f)",
                                              worst_column, worst_measured, worst_expected, worst, tolerance));
    result.summary = format_text("smear profile within %.4f of the analytic one (worst column %d: %.4f vs %.4f; "
                                 "tolerance %.4f)",
                                 worst, worst_column, worst_measured, worst_expected, tolerance);
    return result;
}

CheckResult check_dispersion(const Image& test, const std::string& direction, double min_separation) {
    CheckResult result;
    const int axis = direction.back() == 'x' ? 0 : 1;
    const double sign = direction.front() == '-' ? -1.0 : 1.0;
    double centroid[3];
    for (int c = 0; c < 3; ++c) {
        double weight = 0.0, moment = 0.0;
        for (int y = 0; y < test.height; ++y)
            for (int x = 0; x < test.width; ++x) {
                const double v = test.rgb[(std::size_t(y) * test.width + x) * 3 + c];
                if (!(v > 0.0) || !std::isfinite(v)) continue;
                weight += v;
                moment += v * (axis == 0 ? x : y);
            }
        if (!(weight > 0.0)) {
            result.failures.push_back(format_text("dispersion: channel %s is black", CHANNEL_NAMES[c]));
            result.summary = result.failures.back();
            return result;
        }
        centroid[c] = sign * moment / weight;  // along the direction red -> blue should go
    }
    const double separation = centroid[2] - centroid[0];
    if (!(centroid[0] < centroid[1] && centroid[1] < centroid[2]))
        result.failures.push_back(format_text("dispersion: the channels' centroids along %s are R %.3f, G %.3f, B %.3f px: "
                                              "not in the order red, green, blue",
                                              direction.c_str(), centroid[0], centroid[1], centroid[2]));
    if (!(separation >= min_separation))
        result.failures.push_back(format_text("dispersion: blue lies %.3f px from red along %s, less than %g",
                                              separation, direction.c_str(), min_separation));
    result.summary = format_text("centroids along %s: R %.3f, G %.3f, B %.3f px (red to blue %.3f px; at least %g)",
                                 direction.c_str(), centroid[0], centroid[1], centroid[2], separation, min_separation);
    return result;
}

}  // namespace fh
