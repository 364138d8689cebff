// Checks shaders/lib/sampling/sampling.glsl on the CPU: each warp against its density by a chi-square test
// (Mitsuba 3 style), the frame's orthonormality, the MIS weight's limits, and finiteness at the edges of u.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <random>

#include "chi_square.h"
#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/sampling/sampling.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;
using fh::test::chi_square_test;

constexpr int SAMPLES = 1000000;
const float ONE_MINUS_EPS = 1.0f - 1.0f / 16777216.0f;  // largest float the RNG returns

vec2 random_u2(std::mt19937& rng) {
    std::uniform_real_distribution<float> d(0.0f, 1.0f);
    return vec2(d(rng), d(rng));
}

void expect_pass(const fh::test::ChiSquareResult& r, const char* what) {
    ASSERT_TRUE(r.error.empty()) << what << ": " << r.error;
    const double alpha = fh::test::corrected_significance(fh::test::UNIT_CHI_SQUARE_TESTS);
    EXPECT_GT(r.p_value, alpha) << what << ": chi2 = " << r.statistic << ", dof = " << r.dof;
    std::printf("[chi2] %-28s chi2 %10.1f dof %5d p %.4f\n", what, r.statistic, r.dof, r.p_value);
}

TEST(Sampling, GammaQMatchesClosedForms) {
    for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
        EXPECT_NEAR(fh::test::gamma_q(1.0, x), std::exp(-x), 1e-12 * std::max(1.0, std::exp(-x)) + 1e-300);
        EXPECT_NEAR(fh::test::gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-12);
    }
    // Chi-square with 2000 dof: the median is close to dof (1 - 2/(9 dof))^3.
    EXPECT_NEAR(fh::test::gamma_q(1000.0, 0.5 * 2000.0 * std::pow(1.0 - 2.0 / 18000.0, 3.0)), 0.5, 1e-3);
}

TEST(Sampling, FrameIsOrthonormalAndRoundTrips) {
    std::mt19937 rng(1);
    std::normal_distribution<float> g;
    std::vector<vec3> normals{vec3(0, 0, 1), vec3(0, 0, -1), vec3(1, 0, 0), vec3(0, -1, 0),
                              normalize(vec3(1e-7f, 0, -1)), normalize(vec3(0, 1e-7f, 1)), vec3(0, 1, -0.0f)};
    for (int i = 0; i < 10000; ++i) normals.push_back(normalize(vec3(g(rng), g(rng), g(rng))));
    for (vec3 n : normals) {
        Frame f = make_frame(n);
        EXPECT_NEAR(dot(f.t, f.t), 1.0f, 1e-5f);
        EXPECT_NEAR(dot(f.b, f.b), 1.0f, 1e-5f);
        EXPECT_NEAR(dot(f.t, f.b), 0.0f, 1e-5f);
        EXPECT_NEAR(dot(f.t, n), 0.0f, 1e-5f);
        EXPECT_NEAR(dot(f.b, n), 0.0f, 1e-5f);
        EXPECT_NEAR(dot(cross(f.t, f.b), n), 1.0f, 1e-5f);  // right-handed: local z is n
        vec3 v = normalize(vec3(0.3f, -0.5f, 0.8f));
        vec3 l = to_local(f, v);
        EXPECT_NEAR(l.z, dot(v, n), 1e-6f);
        EXPECT_LT(length(to_world(f, l) - v), 1e-5f);
    }
}

TEST(Sampling, CosineHemisphereChiSquare) {
    fh::test::HemisphereGrid grid;
    std::vector<double> observed(grid.cells(), 0.0), expected(grid.cells());
    std::mt19937 rng(2);
    for (int i = 0; i < SAMPLES; ++i) {
        vec3 w = sample_cosine_hemisphere(random_u2(rng));
        ASSERT_NEAR(length(w), 1.0f, 1e-5f);
        observed[grid.cell_of(w.x, w.y, w.z)] += 1.0;
    }
    // Exact cell integrals: int cos/pi dcos dphi = (c1^2 - c0^2) / 2 * dphi / pi.
    for (int i = 0; i < grid.res_cos; ++i)
        for (int j = 0; j < grid.res_phi; ++j) {
            const double c0 = double(i) / grid.res_cos, c1 = double(i + 1) / grid.res_cos;
            expected[i * grid.res_phi + j] = SAMPLES * 0.5 * (c1 * c1 - c0 * c0) * (2.0 / grid.res_phi);
        }
    expect_pass(chi_square_test(observed, expected), "cosine hemisphere");
    // The warp's own pdf agrees with cos/pi.
    EXPECT_FLOAT_EQ(pdf_cosine_hemisphere(1.0f), INV_PI);
    EXPECT_EQ(pdf_cosine_hemisphere(-0.5f), 0.0f);
}

TEST(Sampling, UniformTriangleChiSquare) {
    const int res = 64;
    std::vector<double> observed(res * res, 0.0), expected(res * res);
    std::mt19937 rng(3);
    for (int i = 0; i < SAMPLES; ++i) {
        vec2 b = sample_uniform_triangle(random_u2(rng));
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LT(b.x + b.y, 1.0f);
        observed[std::min(int(b.x * res), res - 1) * res + std::min(int(b.y * res), res - 1)] += 1.0;
    }
    // Area of cell and {x + y <= 1} by inclusion-exclusion of the corner wedges, F(t) = max(t, 0)^2 / 2.
    auto wedge = [](double t) { return t > 0.0 ? 0.5 * t * t : 0.0; };
    for (int i = 0; i < res; ++i)
        for (int j = 0; j < res; ++j) {
            const double x0 = double(i) / res, x1 = double(i + 1) / res, y0 = double(j) / res, y1 = double(j + 1) / res;
            const double area = wedge(1 - x0 - y0) - wedge(1 - x1 - y0) - wedge(1 - x0 - y1) + wedge(1 - x1 - y1);
            expected[i * res + j] = SAMPLES * 2.0 * area;  // pdf 2 on the triangle of area 1/2
        }
    expect_pass(chi_square_test(observed, expected), "uniform triangle");
}

// Area of the square [x0,x1]x[y0,y1] inside the convex polygon `poly` (counter-clockwise): the square clipped by
// each edge's half-plane (Sutherland-Hodgman), then the shoelace formula.
double clipped_area(const std::vector<std::array<double, 2>>& poly, double x0, double y0, double x1, double y1) {
    std::vector<std::array<double, 2>> shape = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    for (size_t e = 0; e < poly.size() && !shape.empty(); ++e) {
        const auto a = poly[e], b = poly[(e + 1) % poly.size()];
        auto side = [&](const std::array<double, 2>& p) {
            return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);  // >= 0: inside
        };
        std::vector<std::array<double, 2>> kept;
        for (size_t i = 0; i < shape.size(); ++i) {
            const auto p = shape[i], q = shape[(i + 1) % shape.size()];
            const double sp = side(p), sq = side(q);
            if (sp >= 0) kept.push_back(p);
            if ((sp >= 0) != (sq >= 0)) {
                const double t = sp / (sp - sq);
                kept.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
            }
        }
        shape = kept;
    }
    double area = 0;
    for (size_t i = 0; i < shape.size(); ++i) {
        const auto p = shape[i], q = shape[(i + 1) % shape.size()];
        area += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * std::abs(area);
}

// The aperture's points are uniform over the polygon (or, with many blades, close to the disk): the counts in a grid
// over [-1,1]^2 against each cell's area inside the polygon, divided by the polygon's area.
void check_aperture(uint32_t blades, float rotation, const char* what) {
    const int res = 48;
    std::vector<std::array<double, 2>> poly;
    for (uint32_t k = 0; k < blades; ++k)
        poly.push_back({std::cos(rotation + 2 * M_PI * k / blades), std::sin(rotation + 2 * M_PI * k / blades)});
    const double poly_area = 0.5 * blades * std::sin(2 * M_PI / blades);
    std::vector<double> observed(res * res, 0.0), expected(res * res);
    std::mt19937 rng(5 + blades);
    for (int i = 0; i < SAMPLES; ++i) {
        const vec2 p = sample_aperture(random_u2(rng), blades, rotation);
        ASSERT_LE(double(p.x) * p.x + double(p.y) * p.y, 1.0 + 1e-6);
        const int cx = std::clamp(int((p.x + 1.0f) * 0.5f * res), 0, res - 1);
        const int cy = std::clamp(int((p.y + 1.0f) * 0.5f * res), 0, res - 1);
        observed[cy * res + cx] += 1.0;
    }
    for (int cy = 0; cy < res; ++cy)
        for (int cx = 0; cx < res; ++cx) {
            const double x0 = -1.0 + 2.0 * cx / res, y0 = -1.0 + 2.0 * cy / res;
            expected[cy * res + cx] = SAMPLES * clipped_area(poly, x0, y0, x0 + 2.0 / res, y0 + 2.0 / res) / poly_area;
        }
    expect_pass(chi_square_test(observed, expected), what);
}

TEST(Sampling, PolygonalApertureChiSquare) {
    check_aperture(3, 0.0f, "aperture, 3 blades");
    check_aperture(6, 0.3f, "aperture, 6 blades rotated");
    check_aperture(16, 1.0f, "aperture, 16 blades");
}

// Fewer than 3 blades is the disk: the concentric map itself.
TEST(Sampling, ApertureWithoutBladesIsTheDisk) {
    std::mt19937 rng(9);
    for (int i = 0; i < 1000; ++i) {
        const vec2 u = random_u2(rng);
        const vec2 a = sample_aperture(u, 0u, 0.7f), d = sample_concentric_disk(u);
        EXPECT_EQ(a.x, d.x);
        EXPECT_EQ(a.y, d.y);
    }
}

double erfinv_reference(double x) {  // Newton on erf, from a good start
    double y = 0.0;
    for (int i = 0; i < 100; ++i) y -= (std::erf(y) - x) / (2.0 / std::sqrt(M_PI) * std::exp(-y * y));
    return y;
}

TEST(Sampling, ErfinvIsAccurateOnTheFilterRange) {
    double worst = 0.0;
    for (int i = 1; i < 200000; ++i) {
        const float x = 0.9973f * (2.0f * float(i) / 200000.0f - 1.0f);
        if (x == 0.0f) continue;
        const double ref = erfinv_reference(double(x));
        worst = std::max(worst, std::abs(erfinv_approx(x) - ref) / std::abs(ref));
    }
    EXPECT_LT(worst, 1e-6) << "worst relative error " << worst;
    std::printf("erfinv_approx: worst relative error %.3g on |x| <= 0.9973\n", worst);
}

void check_gaussian_filter(float radius, unsigned seed, const char* what) {
    const int res = 48;
    std::vector<double> observed(res * res, 0.0), expected(res * res);
    std::mt19937 rng(seed);
    for (int i = 0; i < SAMPLES; ++i) {
        vec2 o = sample_gaussian_filter(random_u2(rng), radius);
        ASSERT_LE(abs(o.x), radius);
        ASSERT_LE(abs(o.y), radius);
        const int cx = std::clamp(int((o.x + radius) / (2 * radius) * res), 0, res - 1);
        const int cy = std::clamp(int((o.y + radius) / (2 * radius) * res), 0, res - 1);
        observed[cx * res + cy] += 1.0;
    }
    // Separable truncated normal, sigma = radius / 3: exact cell masses from erf.
    const double sigma = radius / 3.0, norm = std::erf(3.0 / std::sqrt(2.0));
    auto mass = [&](int k) {
        const double a = -radius + 2.0 * radius * k / res, b = -radius + 2.0 * radius * (k + 1) / res;
        return 0.5 * (std::erf(b / (sigma * std::sqrt(2.0))) - std::erf(a / (sigma * std::sqrt(2.0)))) / norm;
    };
    for (int i = 0; i < res; ++i)
        for (int j = 0; j < res; ++j) expected[i * res + j] = SAMPLES * mass(i) * mass(j);
    expect_pass(chi_square_test(observed, expected), what);
}

TEST(Sampling, GaussianFilterChiSquare) {
    check_gaussian_filter(1.5f, 4, "gaussian filter r=1.5");
    check_gaussian_filter(0.5f, 6, "gaussian filter r=0.5");
}

TEST(Sampling, PowerHeuristicLimits) {
    EXPECT_FLOAT_EQ(power_heuristic(1.0f, 1.0f), 0.5f);
    EXPECT_FLOAT_EQ(power_heuristic(3.0f, 1.0f), 0.9f);
    EXPECT_FLOAT_EQ(power_heuristic(1.0f, 3.0f), 0.1f);
    EXPECT_EQ(power_heuristic(0.0f, 0.0f), 0.0f);
    EXPECT_EQ(power_heuristic(0.0f, 5.0f), 0.0f);
    EXPECT_EQ(power_heuristic(5.0f, 0.0f), 1.0f);
    const float inf = INFINITY, nan = NAN;
    EXPECT_EQ(power_heuristic(inf, 1.0f), 1.0f);
    EXPECT_EQ(power_heuristic(1.0f, inf), 0.0f);
    EXPECT_FLOAT_EQ(power_heuristic(inf, inf), 0.5f);
    EXPECT_EQ(power_heuristic(nan, 1.0f), 0.0f);
    EXPECT_EQ(power_heuristic(1.0f, nan), 1.0f);
    EXPECT_FLOAT_EQ(power_heuristic(1e30f, 1e30f), 0.5f);   // no overflow of f^2
    EXPECT_FLOAT_EQ(power_heuristic(1e-30f, 1e-30f), 0.5f); // no underflow to 0/0
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> d(-30.0f, 30.0f);
    for (int i = 0; i < 10000; ++i) {
        const float f = std::pow(10.0f, d(rng)), g = std::pow(10.0f, d(rng));
        EXPECT_NEAR(power_heuristic(f, g) + power_heuristic(g, f), 1.0f, 1e-6f);  // weights partition unity
    }
}

TEST(Sampling, LuminanceOfWhiteIsOne) {
    EXPECT_NEAR(luminance(vec3(1.0f)), 1.0f, 1e-6f);
    EXPECT_EQ(luminance(vec3(0.0f)), 0.0f);
}

TEST(Sampling, WarpsAreFiniteAtTheEdgesOfU) {
    const float edges[] = {0.0f, 1e-30f, 1e-7f, 0.25f, 0.5f, 0.75f, 0.9999999f, ONE_MINUS_EPS};
    for (float a : edges)
        for (float b : edges) {
            const vec2 u(a, b);
            const vec3 w = sample_cosine_hemisphere(u);
            EXPECT_TRUE(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) << a << " " << b;
            EXPECT_GE(w.z, 0.0f);
            EXPECT_NEAR(length(w), 1.0f, 1e-5f);
            const vec2 t = sample_uniform_triangle(u);
            EXPECT_TRUE(t.x >= 0.0f && t.y >= 0.0f && t.x + t.y < 1.0f) << a << " " << b;
            const vec2 o = sample_gaussian_filter(u, 2.0f);
            EXPECT_TRUE(std::isfinite(o.x) && std::isfinite(o.y) && abs(o.x) <= 2.0f && abs(o.y) <= 2.0f);
        }
}

}  // namespace
