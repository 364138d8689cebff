// What the stratified sampler buys, on the Cornell box against Mitsuba 3's converged image (../shared/references):
// at equal samples, `--sampler sobol` has several times less error than `--sampler independent` (about 6x at
// 256 x 256 and 64 spp; shaders/lib/integrator/README.md "Sampling"), and neither is biased (image means agree with the reference).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "io/exr.h"
#include "render_image.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(CONVERGE_OUT) / "sampler";
constexpr int SIZE = 64;     // the 256 x 256 reference averaged over 4 x 4 blocks: a box-filtered 64 x 64 pixel's mean
constexpr int SPP = 16;

fh::Image render(const std::string& sampler, unsigned seed) {
    return fh::test::render_image(FREDHOLM_EXE, CORNELL_SCENE, OUT, sampler + "_" + std::to_string(seed),
                                  fh::test::square_render_args(SIZE, SPP, 10, seed) + " --sampler " + sampler);
}

TEST(Sampler, SobolHasSeveralTimesLessErrorThanIndependent) {
    const fh::Image full = fh::read_exr(CORNELL_REFERENCE);
    ASSERT_EQ(full.width, SIZE * 4);
    std::vector<double> reference(size_t(SIZE) * SIZE * 3, 0.0);
    for (int y = 0; y < full.height; ++y)
        for (int x = 0; x < full.width; ++x)
            for (int c = 0; c < 3; ++c)
                reference[((y / 4) * SIZE + x / 4) * 3 + c] += full.rgb[(size_t(y) * full.width + x) * 3 + c] / 16.0;
    double mse[2] = {0, 0}, mean[2] = {0, 0}, reference_mean = 0;
    const char* names[2] = {"independent", "sobol"};
    for (int s = 0; s < 2; ++s)
        for (unsigned seed : {0u, 1u}) {
            const fh::Image image = render(names[s], seed);
            for (size_t p = 0; p < size_t(SIZE) * SIZE; ++p)
                for (int c = 0; c < 3; ++c) {
                    const double d = image.rgb[p * 3 + c] - reference[p * 3 + c];
                    mse[s] += d * d / (SIZE * SIZE * 3 * 2);
                    mean[s] += image.rgb[p * 3 + c] / (SIZE * SIZE * 3 * 2);
                    if (s == 0 && seed == 0) reference_mean += reference[p * 3 + c] / (SIZE * SIZE * 3);
                }
        }
    std::printf("[sampler] Cornell 64 x 64, 16 spp, two seeds: MSE independent %.3e, sobol %.3e (%.1fx); means %.5f, %.5f, "
                "reference %.5f\n", mse[0], mse[1], mse[0] / mse[1], mean[0], mean[1], reference_mean);
    EXPECT_LT(mse[1], mse[0] / 3.0);
    for (int s = 0; s < 2; ++s) EXPECT_NEAR(mean[s], reference_mean, 0.01 * reference_mean) << names[s];
}

}  // namespace
