// Whole-image checks for render tests: statistical comparison against a reference, furnace constancy,
// bit-identity and finiteness. Each check returns a result; the fh_compare tool only prints it.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "io/image.h"

namespace fh {

// What every check returns: no failures = pass. `difference` is a per-pixel image explaining a failure
// (empty when the images cannot be lined up, e.g. sizes differ).
struct CheckResult {
    std::vector<std::string> failures;  // one line per failing criterion
    std::string summary;                // one line with the numbers, pass or fail
    Image difference;
    bool passed() const { return failures.empty(); }
};

// ---- Comparison against a reference --------------------------------------------------------------------
//
// Mean test: for R, G, B and luminance (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B) the relative difference of
// the image means |mean_t - mean_r| / |mean_r| must not exceed max_mean_rel. No noise allowance: over 65536
// pixels the image mean of a usable render is far more precise than 0.5%, and a global bias (a missing pi, a
// lost bounce) shows up here first. At very low spp pick max_mean_rel above ~4 standard errors of the mean.
//
// Block test: the image is cut into block x block tiles (edge tiles may be smaller). For every tile k and
// channel c, with t and r the tile means of test and reference:
//   rel = |t - r| / max(r, floor_c),  floor_c = 1e-2 * (image mean of reference channel c)
//         (so nearly black tiles do not turn tiny absolute differences into huge relative ones)
//   z   = (t - r) / se,  se = std(residual) / sqrt(n),  residual = test - reference per pixel, n pixels,
//         std with n - 1 (the tile's own noise; subtracting the reference first removes edges and texture
//         so only Monte Carlo noise of both images remains). se = 0 gives z = 0 if t == r, else infinity.
//   z_crit = the two-sided normal quantile for alpha / (tiles * 3): Bonferroni, so a correct renderer fails
//            the significance part with probability at most alpha (0.01) per image.
// A tile FAILS iff |z| > z_crit AND rel > max_block_rel. Why both:
//   - significance alone would fail converged images for differences far below anything visible (two
//     independent renderers differ by ~0.5% systematically: different bounce limits, float rounding; an
//     emitter tile is constant in both images, so se = 0 and 18.3873 vs 18.3870 is "infinitely significant");
//   - relative size alone would fail low-spp test images on pure noise (a 16x16 tile at 64 spp in a dark
//     corner easily deviates 5%).
// So noise never fails and a small systematic difference never fails; a difference that is both real and
// large does. Nothing passes silently: the summary always reports how many tiles exceed each part alone, and
// the worst tile by rel and by |z| (position, channel, test and reference means), and a global bias too small
// per tile is caught by the mean test.
//
// On failure `difference` holds test - reference per pixel and `z_image` each tile's (t - r) / se painted
// over its pixels (signed, per channel; infinity where se = 0 and t != r).

struct ReferenceOptions {
    int block = 16;
    double max_block_rel = 0.05;
    double max_mean_rel = 0.005;
    double alpha = 0.01;
};

struct BlockStat {
    int x = 0, y = 0;  // top-left pixel of the tile
    int channel = 0;   // 0 R, 1 G, 2 B
    double test_mean = 0, reference_mean = 0, rel = 0, z = 0;
};

struct ReferenceResult : CheckResult {
    std::array<double, 4> test_mean{}, reference_mean{}, mean_rel{};  // R, G, B, luminance
    int tiles = 0;              // number of tiles (each tested in 3 channels)
    double z_critical = 0;      // Bonferroni threshold on |z|
    BlockStat worst_rel, worst_z;
    int over_rel = 0;           // tile-channels with rel > max_block_rel
    int over_z = 0;             // tile-channels with |z| > z_critical
    int failing_blocks = 0;     // tile-channels with both
    Image z_image;
};

ReferenceResult compare_to_reference(const Image& test, const Image& reference, const ReferenceOptions& options = {});

// ---- Other checks --------------------------------------------------------------------------------------

// Furnace test: every channel of every pixel (minus `ignore_border` pixels on each side) must satisfy
// |v - value| <= tolerance * |value| (absolute tolerance when value is 0), and each channel's mean over those
// pixels must be within `mean_tolerance` (negative: tolerance / 10) in the same sense. `difference` = test - value.
// The second form expects a colour: channel c against value[c].
CheckResult check_constant(const Image& test, double value, double tolerance = 0.01, int ignore_border = 0,
                           double mean_tolerance = -1);
CheckResult check_constant(const Image& test, const std::array<double, 3>& value, double tolerance = 0.01,
                           int ignore_border = 0, double mean_tolerance = -1);

// Bit-identical pixel data (NaNs compare by bit pattern); reports the first differing pixel.
CheckResult check_identical(const Image& test, const Image& other);

// Every value finite; `difference` is 1 where a channel is NaN or infinite, else 0.
CheckResult check_finite(const Image& test);

// The image's light is spread along image axis `axis` ('x': left-right, 'y': top-bottom) at least `min_ratio` times
// as widely as across it: the luminance-weighted variance of the pixel coordinate along the axis over the one across
// it (e.g. an anisotropic highlight, stretched along the rougher direction). No difference image.
CheckResult check_elongation(const Image& test, char axis, double min_ratio);

// The image's light is split by colour along `direction` ("x", "-x", "y" or "-y"; +y is down the image): the
// intensity-weighted centroids of R, G and B lie in that order along it, blue at least `min_separation` pixels beyond
// red (a prism's spectrum: shorter wavelengths bend more). No difference image.
CheckResult check_dispersion(const Image& test, const std::string& direction, double min_separation);

// A point of light blurred by a lens: the test image is `sharp` (the same light through a pinhole) spread over a
// disk of diameter `expected_px` pixels, within `tolerance_px`. Luminance-weighted second moments about each image's
// centroid add under convolution, and a uniform disk of diameter c has E[r^2] = c^2 / 8, so the measured diameter is
// sqrt(8 (m2(test) - m2(sharp))). A polygonal aperture's blur has the same E[r^2] as the disk whose diameter the test
// expects (the caller converts). No difference image.
CheckResult check_blur_diameter(const Image& test, const Image& sharp, double expected_px, double tolerance_px);

// A bar of radiance 1 on black, `width_px` wide, moving along +x at a constant speed while the shutter is open: its
// left edge at `left_px` (image x, pixels from the left) at open and `travel_px` further on at close. Each pixel of a
// box-filtered render then reads the time its footprint was covered, averaged over the footprint: the bar's box
// convolved with the box of its travel (a trapezoid), integrated over the pixel. The test: in every column, the mean
// of the luminance over rows [row_begin, row_end) (inside the bar) lies within `tolerance` of that. No difference
// image.
CheckResult check_smear_profile(const Image& test, double left_px, double width_px, double travel_px, int row_begin,
                                int row_end, double tolerance);

// ---- Same distribution, pixel by pixel -----------------------------------------------------------------
//
// test and reference are K >= 2 independent renders each (different seeds) of images that should have the
// same expected value in every pixel (e.g. a scene and the same scene scaled by 1e4). Per pixel and channel,
// Welch's t statistic of the two sets of batch means, t = (m_t - m_r) / sqrt(s_t^2/K_t + s_r^2/K_r), with
// Welch-Satterthwaite degrees of freedom, gives a two-sided p-value from Student's t; a value fails when
// p < alpha / (pixels x 3) (Bonferroni: a correct renderer fails with probability at most alpha). Batch means
// of >= 64 samples are close enough to normal for the t test. Both noiseless but different: p = 0.

struct DistributionResult : CheckResult {
    size_t tests = 0;            // pixels x 3
    size_t failing = 0;
    double p_critical = 0;
    double worst_p = 1;
    size_t worst_index = 0;      // into rgb
    double worst_test_mean = 0, worst_reference_mean = 0;
};

DistributionResult compare_distributions(const std::vector<Image>& test, const std::vector<Image>& reference,
                                         double alpha = 0.01);

// ---- Statistics helpers (exposed for tests) ------------------------------------------------------------

// I_x(a, b), and the two-sided tail P(|T| > |t|) of Student's t with `dof` degrees of freedom.
double regularized_incomplete_beta(double a, double b, double x);
double student_t_two_sided_p(double t, double dof);

// The z with P(Z > z) = upper_tail for a standard normal Z (upper_tail in (0, 0.5]).
double normal_upper_quantile(double upper_tail);

// Two-sided Bonferroni threshold: |z| above it has probability alpha / tests under the null hypothesis.
double bonferroni_z_threshold(double alpha, std::size_t tests);

double luminance(float r, float g, float b);

}  // namespace fh
