// What picking the light with its point's 2D sample buys (`--light-pick reuse`, the default, against `separate`;
// shaders/lib/light/lights.glsl, shaders/lib/integrator/README.md "Sampling"), against an analytic image: a diffuse floor under a quad light of two
// triangles (make_asset_scenes.py quad_light_floor.gltf). With --max-depth 2 a floor point reads
// rho x L x F, F its form factor to the light's rectangle (the parallel-rectangle formula below), and a box-filtered
// pixel the mean of that over its square. Both modes must converge to it, and reuse must have less error at equal
// samples: with the pick apart, the light's 2D points split between the two triangles at random.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/exr.h"
#include "render_image.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(CONVERGE_OUT) / "light_pick";
constexpr int SIZE = 64;
constexpr int SPP = 16;
// make_asset_scenes.py: QUAD_FLOOR_RHO, QUAD_LIGHT_HALF, QUAD_LIGHT_HEIGHT, QUAD_LIGHT_RADIANCE.
constexpr double RHO = 0.5, HALF = 0.5, HEIGHT = 0.5, RADIANCE = 4.0;

// Form factor from a floor point at the origin, facing up, to the parallel rectangle [0, x] x [0, y] at `HEIGHT`
// above it (odd in x and in y, so that signed corners add up to any rectangle).
double corner_form_factor(double x, double y) {
    const double a = x / HEIGHT, b = y / HEIGHT;
    const double sa = std::sqrt(1.0 + a * a), sb = std::sqrt(1.0 + b * b);
    return (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb)) / (2.0 * M_PI);
}

double form_factor(double px, double py) {
    const double x0 = -HALF - px, x1 = HALF - px, y0 = -HALF - py, y1 = HALF - py;
    return corner_form_factor(x1, y1) - corner_form_factor(x0, y1) - corner_form_factor(x1, y0) +
           corner_form_factor(x0, y0);
}

// The box-filtered pixel (i, j) of the 2 x 2 view: the mean of rho L F over its square, 8 x 8 midpoints (F is smooth
// on the floor: the error is far below the renders' noise). The image is symmetric in x and y, so its orientation
// does not matter.
double analytic_pixel(int i, int j) {
    const double w = 2.0 / SIZE;
    double sum = 0.0;
    for (int v = 0; v < 8; ++v)
        for (int u = 0; u < 8; ++u) sum += form_factor(-1.0 + w * (i + (u + 0.5) / 8.0), -1.0 + w * (j + (v + 0.5) / 8.0));
    return RHO * RADIANCE * sum / 64.0;
}

fh::Image render(const std::string& pick, unsigned seed) {
    return fh::test::render_image(FREDHOLM_EXE, QUAD_LIGHT_SCENE, OUT, pick + "_" + std::to_string(seed),
                                  fh::test::square_render_args(SIZE, SPP, 2, seed) + " --light-pick " + pick);
}

TEST(LightPick, ReuseHasLessErrorAndBothConvergeToTheAnalyticImage) {
    std::vector<double> reference(size_t(SIZE) * SIZE);
    double reference_mean = 0.0;
    for (int j = 0; j < SIZE; ++j)
        for (int i = 0; i < SIZE; ++i) {
            reference[size_t(j) * SIZE + i] = analytic_pixel(i, j);
            reference_mean += reference[size_t(j) * SIZE + i] / (SIZE * SIZE);
        }
    const char* names[2] = {"separate", "reuse"};
    constexpr unsigned SEEDS = 4;
    double mse[2] = {0, 0}, mean[2] = {0, 0};
    for (int s = 0; s < 2; ++s)
        for (unsigned seed = 0; seed < SEEDS; ++seed) {
            const fh::Image image = render(names[s], seed);
            ASSERT_EQ(image.width, SIZE);
            for (size_t p = 0; p < size_t(SIZE) * SIZE; ++p)
                for (int c = 0; c < 3; ++c) {
                    const double d = image.rgb[p * 3 + c] - reference[p];
                    mse[s] += d * d / (SIZE * SIZE * 3 * SEEDS);
                    mean[s] += image.rgb[p * 3 + c] / (SIZE * SIZE * 3 * SEEDS);
                }
        }
    std::printf("[light pick] quad light over a floor, 64 x 64, %d spp, %u seeds: MSE separate %.3e, reuse %.3e "
                "(%.2fx); means %.5f, %.5f, analytic %.5f\n", SPP, SEEDS, mse[0], mse[1], mse[0] / mse[1], mean[0],
                mean[1], reference_mean);
    EXPECT_LT(mse[1], 0.8 * mse[0]);
    for (int s = 0; s < 2; ++s) EXPECT_NEAR(mean[s], reference_mean, 0.002 * reference_mean) << names[s];
}

}  // namespace
