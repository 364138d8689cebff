// The environment light: the map's sampling table (scene/light/environment.cpp) and the very GLSL the stages run
// (shaders/lib/light/environment.glsl compiled as C++): samples follow the claimed pdf (chi-square over texels),
// the pdf a sample reports is the pdf of its direction, the pdf integrates to 1 over the sphere, directions
// and texture coordinates invert each other, and a constant background is sampled by sin(theta).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "chi_square.h"
#include "scene/light/environment.h"
#include "shared/layout.h"
#include "lib/core/cpp_compat.h"

namespace fh::glsl {
using fh::gpu::FrameParams;
FrameParams params{};
std::vector<glm::vec4> env_radiance;
std::vector<float> env_cdf;
#include "lib/light/environment.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;

// A 32 x 16 map with a bright "sun", a sky gradient, a black band and a dim ground.
fh::EnvironmentMap make_test_map(float rotation) {
    const uint32_t w = 32, h = 16;
    std::vector<float> rgb;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float v = y < h / 2 ? 1.0f + 0.2f * float(x) : 0.05f;
            if (y == 5) v = 0.0f;
            if (x == 9 && y == 3) v = 500.0f;
            rgb.insert(rgb.end(), {v, 0.5f * v, 0.25f * v});
        }
    return fh::make_environment_map(w, h, rgb, 2.0f, rotation, "test");
}

void install(const fh::EnvironmentMap& env) {
    params = FrameParams{};
    params.env_width = env.width;
    params.env_height = env.height;
    params.env_rotation = env.rotation;
    env_radiance = env.texels;
    env_cdf = env.cdf;
}

TEST(Environment, DirectionsAndTexcoordsInvertEachOther) {
    install(make_test_map(0.7f));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.001f, 0.999f);
    for (int i = 0; i < 1000; ++i) {
        const vec2 uv(u(rng), u(rng));
        const vec2 back = env_texcoord(env_direction(uv));
        EXPECT_NEAR(back.x, uv.x, 1e-4f);
        EXPECT_NEAR(back.y, uv.y, 1e-4f);
    }
    // The documented mapping (Blender's, probed with Cycles): without rotation the centre column looks down +X,
    // u = 0.25 down -Z, u = 0.75 down +Z, the top row up +Y.
    params.env_rotation = 0.0f;
    EXPECT_NEAR(env_direction(vec2(0.5f, 0.5f)).x, 1.0f, 1e-6f);
    EXPECT_NEAR(env_direction(vec2(0.25f, 0.5f)).z, -1.0f, 1e-6f);
    EXPECT_NEAR(env_direction(vec2(0.75f, 0.5f)).z, 1.0f, 1e-6f);
    EXPECT_NEAR(env_direction(vec2(0.3f, 0.0f)).y, 1.0f, 1e-6f);
}

TEST(Environment, SamplesReportThePdfOfTheirDirection) {
    install(make_test_map(0.7f));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int mismatches = 0;
    for (int i = 0; i < 100000; ++i) {
        const EnvironmentSample s = sample_environment(vec2(u(rng), u(rng)));
        ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.0f);
        const float pdf = pdf_environment(s.dir);
        const vec3 radiance = eval_environment(s.dir);
        // A direction on a texel border may round into the neighbour: allow a handful.
        if (std::abs(pdf - s.pdf) > 1e-3f * s.pdf || radiance != s.radiance) ++mismatches;
    }
    EXPECT_LT(mismatches, 20);
}

TEST(Environment, PdfIntegratesToOneOverTheSphere) {
    install(make_test_map(-1.3f));
    // Midpoint rule over the map, 8 x 8 points per texel: d omega = 2 pi^2 sin(theta) du dv.
    const int nu = 256, nv = 128;
    double sum = 0.0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const vec2 uv(float((i + 0.5) / nu), float((j + 0.5) / nv));
            sum += pdf_environment(env_direction(uv)) * 2.0 * M_PI * M_PI * std::sin(M_PI * uv.y);
        }
    EXPECT_NEAR(sum / (nu * nv), 1.0, 1e-4);
}

// Chi-square over texels: each texel's probability is its luminance x sin(theta) share (what the table says),
// the histogram is of the sampled directions mapped back to texels.
TEST(Environment, SamplesFollowLuminanceTimesSinTheta) {
    const fh::EnvironmentMap env = make_test_map(2.1f);
    install(env);
    const size_t n = 400000;
    std::vector<double> observed(size_t(env.width) * env.height, 0.0), expected(observed.size(), 0.0);
    double total_weight = 0.0;
    for (uint32_t y = 0; y < env.height; ++y)
        for (uint32_t x = 0; x < env.width; ++x) {
            const glm::vec4 c = env.texels[y * env.width + x];
            const double weight = (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b) * std::sin(M_PI * (y + 0.5) / env.height);
            expected[y * env.width + x] = weight;
            total_weight += weight;
        }
    for (double& e : expected) e *= double(n) / total_weight;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (size_t i = 0; i < n; ++i) observed[env_texel_index(env_texcoord(sample_environment(vec2(u(rng), u(rng))).dir))] += 1.0;
    const fh::test::ChiSquareResult r = fh::test::chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.error;
    EXPECT_GT(r.p_value, 0.001) << "chi-square " << r.statistic << " with " << r.dof << " dof";
    EXPECT_EQ(observed[5 * env.width + 4], 0.0) << "a black texel was sampled";
}

TEST(Environment, ConstantBackgroundIsSampledBySinTheta) {
    const fh::EnvironmentMap env = fh::make_constant_environment(glm::vec3(1.0f));
    install(env);
    EXPECT_NEAR(env.luminance_integral, 4.0 * M_PI, 0.01);
    // Uniform radiance: the density is 1 / (4 pi) at each row's centre; within a row it goes as
    // sin(theta at the centre) / sin(theta), piecewise constant in (u, v) as pbrt-v4's is.
    for (int row : {3, 10, 16, 27}) {
        const float theta = float(M_PI) * (row + 0.5f) / 32.0f;
        EXPECT_NEAR(pdf_environment(vec3(std::sin(theta), std::cos(theta), 0.0f)) * 4.0f * float(M_PI), 1.0f, 0.003f);
    }
}

TEST(Environment, RejectsNonFiniteTexelsAndClampsNegativeOnes) {
    std::vector<float> rgb(8 * 4 * 3, 1.0f);
    rgb[7] = -0.01f;
    const fh::EnvironmentMap env = fh::make_environment_map(8, 4, rgb, 1.0f, 0.0f, "test");
    EXPECT_EQ(env.clamped_texels, 1u);
    EXPECT_EQ(env.texels[2].g, 0.0f);
    rgb[5] = NAN;
    EXPECT_THROW(fh::make_environment_map(8, 4, rgb, 1.0f, 0.0f, "test"), std::invalid_argument);
}

}  // namespace
