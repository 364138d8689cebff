// Do two renders differ beyond their Monte Carlo noise? The statistics of `fredholm compare`: each pixel's luminance
// difference against the two images' variance layers (render/error_estimate.h), per pixel and per tile, with the
// false-alarm rate over the whole image held at alpha by Bonferroni's bound. See README.md beside this file.
#pragma once
#include <cstdint>
#include <vector>

#include "io/image.h"

namespace fh {

// An image with the variance of each pixel's mean luminance (variance.Y) and its degrees of freedom (complete
// batches - 1); no variance: `variance` empty.
struct NoisyImage {
    Image image;
    std::vector<float> variance;
    uint32_t degrees_of_freedom = 0;
};

struct CompareOptions {
    double alpha = 0.01;      // the chance that two renders of the same scene are called different
    int tile = 16;            // tile side in pixels
    double threshold = 0.02;  // without variance layers: the relative difference above which they differ
};

struct TileVerdict {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) x [y0, y1)
    double mean_z = 0;     // the tile's summed difference over its standard deviation
    double spread = 0;     // sum of d^2 over sum of variances (1 on average when they agree)
    double score = 0;      // the larger of |mean_z| / its limit and spread / its limit: above 1 is significant
    bool significant = false;
};

struct CompareResult {
    bool with_noise = false;             // both images had variance layers
    bool differs = false;
    double relative_difference = 0;     // sqrt(mean over pixels of d^2 / (Y^2 + 0.01)), Y the two images' mean
    double relative_noise = 0;          // sqrt(mean over pixels of (var_a + var_b) / (Y^2 + 0.01))
    size_t pixels = 0, significant_pixels = 0;
    size_t tiles = 0, significant_tiles = 0;
    double pixel_limit = 0;             // |d| / sigma above this is a significant pixel
    double tile_z_limit = 0;            // |mean_z| above this is a significant tile
    std::vector<TileVerdict> worst;     // the tiles with the highest scores, highest first (at most 3)
    std::vector<float> pixel_z;         // |d| / sigma per pixel (empty without noise)
    std::vector<uint8_t> pixel_significant;
    std::vector<TileVerdict> tile_verdicts;
};

// Throws std::invalid_argument when the images differ in size.
CompareResult compare_images(const NoisyImage& a, const NoisyImage& b, const CompareOptions& options);

// Quantiles: the z with P(Z > z) = upper for the standard normal; the t with P(T > t) = upper for Student's t.
double normal_upper_quantile(double upper);
double student_t_upper_quantile(double upper, double degrees_of_freedom);
// P(T > t) for Student's t with `dof` degrees of freedom.
double student_t_upper_tail(double t, double dof);

}  // namespace fh
