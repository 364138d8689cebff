// Error of a render against a reference, and what a convergence curve says: log-log slopes, bias floor, time to
// reach a target error. CPU only; `fredholm converge` and tests/converge use it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "io/image.h"
#include "render/settings.h"

namespace fh {

// Guard in every relative metric: relMSE = mean (x - r)^2 / (r^2 + REL_EPS), MAPE = mean |x - r| / (|r| + REL_EPS).
constexpr double REL_EPS = 1e-2;
// Target relMSE values the report gives times for.
constexpr double TARGET_RELMSE[3] = {1e-2, 5e-3, 1e-3};

// Errors of one image, as means over all pixels and the three channels (non-finite values are skipped and
// counted). The variance and bias fields need the previous image of the same progressive film.
struct ImageErrors {
    double mse = 0, relmse = 0, mape = 0;
    uint64_t nonfinite = 0;
    bool has_variance = false;
    // Var(x) estimated from the film at a smaller spp a: mean (x_a - x)^2 * a / (n - a). The n - a newer
    // samples are independent of the first a, so this is unbiased for the variance of the n-spp mean.
    double variance = 0, rel_variance = 0;
    // Squared bias: mse - variance - (the reference's own variance, when known), and its standard error over
    // pixels. Unbiased for the mean squared bias of the expected image; ~0 within noise for an unbiased config.
    double bias2 = 0, bias2_stderr = 0, rel_bias2 = 0, rel_bias2_stderr = 0;
};

// A half-spp image of the same film, with the sample counts of both, for the variance estimate.
struct EarlierImage {
    const Image* image = nullptr;
    uint32_t spp = 0;       // samples in `image`
    uint32_t spp_now = 0;   // samples in the image being measured
};

// Errors of `x` against `reference`; `earlier` (optional) gives the variance and bias estimates, and
// `reference_earlier` (optional) the reference's own variance, which is then subtracted from the bias.
ImageErrors measure_errors(const Image& x, const Image& reference, const EarlierImage& earlier = {},
                           const EarlierImage& reference_earlier = {});
// Two independent renders a, b of the same configuration and spp: mse = mean (a - b)^2 / 2 estimates the
// variance part of the error only (no bias); relative metrics use (a + b) / 2 as the reference, and
// MAPE = mean |a - b| / sqrt(2) / (|m| + eps) (exact for Gaussian noise).
ImageErrors measure_two_seed_errors(const Image& a, const Image& b);
// Mean over pixels of (x_a - x)^2 * a / (n - a): the variance of the n-spp image of a progressive film.
double estimate_variance(const Image& x, const EarlierImage& earlier);

struct ConvergeStep {
    uint32_t spp = 0;
    double seconds = 0;  // cumulative render time (GPU wave loop) of all steps up to this one
    ImageErrors errors;
};

struct ConvergeCurve {
    std::string name;  // "default" or "KEY=VALUE"
    RenderSettings settings;
    std::vector<ConvergeStep> steps;
    std::string stop_reason;  // "max-spp", "time budget", "interrupted"
};

// Time to reach a target relMSE: interpolated between steps, extrapolated past the budget, or never.
struct TargetTime {
    enum Kind { reached, extrapolated, never } kind = never;
    double seconds = 0;
};

struct CurveSummary {
    double slope_mse_spp = 0, slope_mse_seconds = 0, slope_relmse_seconds = 0;  // least squares in log-log
    uint32_t fit_steps = 0;
    double samples_per_second = 0;  // width * height * spp / seconds at the last step
    double efficiency = 0;          // 1 / (MSE * seconds) at the last step
    bool has_bias = false;
    double bias2 = 0, bias2_stderr = 0, rel_floor = 0, rel_floor_stderr = 0;
    bool floor_significant = false;  // rel_floor > 3 standard errors
    TargetTime time_to[3];           // for TARGET_RELMSE
};

// Slopes are fitted to the last FIT_STEPS steps: the asymptotic regime; the first steps of a small film are
// dominated by per-dispatch costs that do not grow with spp.
constexpr uint32_t FIT_STEPS = 6;
double fit_loglog_slope(const std::vector<double>& x, const std::vector<double>& y);
CurveSummary summarize_curve(const ConvergeCurve& curve, uint32_t width, uint32_t height);
// log-log interpolation of the first crossing of `target`; beyond the last step, relMSE - floor is assumed to
// fall as 1 / seconds (the unbiased Monte Carlo rate); never when a significant floor is at or above target.
TargetTime time_to_reach(const std::vector<ConvergeStep>& steps, double rel_floor, bool floor_significant,
                         double target);

}  // namespace fh
