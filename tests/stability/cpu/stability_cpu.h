// What the CPU stability tests share on top of tests/unit's chi_square.h and ggx_albedo_reference.h: the
// renderer's random-number lattice, the edge values of u, an independent double-precision GGX (distribution,
// Smith masking, visible normals) with the "stretch" map that turns a sharp lobe into a smooth density, and a
// quadrature for densities cut off along a curve. No .glsl here: each test executable includes the one
// library it checks.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "chi_square.h"
#include "ggx_albedo_reference.h"

namespace fh::test::stability {

// Every chi-square test of ctest -L stability (CPU), each histogram counted twice (fine and coarse, below):
// test_sampling_extremes 2 x 31, test_bsdf_grazing_chi_square 2 x 41. Keep it up to date when adding one: it
// sets each test's significance (corrected_significance).
inline constexpr int STABILITY_CHI_SQUARE_TESTS = 2 * (31 + 41);

// Every histogram is tested twice: on its fine grid (64 x 128 cells, ~120 samples each: sharp features) and
// summed into 8 x 8 blocks (~7800 samples each: a smooth 1% error in the density, which adds too little to
// the statistic of 8000 small cells to stand out, moves these by several standard deviations).
inline constexpr int COARSE_BLOCK = 8;
inline std::vector<double> coarsen(const std::vector<double>& cells, int rows, int columns) {
    std::vector<double> out((rows / COARSE_BLOCK) * (columns / COARSE_BLOCK), 0.0);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < columns; ++j)
            out[(i / COARSE_BLOCK) * (columns / COARSE_BLOCK) + j / COARSE_BLOCK] += cells[i * columns + j];
    return out;
}

// Uniform floats on the renderer's lattice (rng.glsl next_float: 24 random bits times 2^-24), so 0 and
// 1 - 2^-24 are values the renderer can produce and 1 is not.
struct Rng {
    std::mt19937 engine;
    explicit Rng(uint32_t seed) : engine(seed) {}
    float uniform() { return float(engine() >> 8) * 0x1p-24f; }
};

inline constexpr float ONE_MINUS_EPS = 1.0f - 0x1p-24f;  // the largest float next_float returns
// u components at and next to the ends and the middle of [0, 1): the smallest denormal, 2^-24 (the smallest
// non-zero lattice value), both neighbours of 0.5 (where the concentric map changes wedge), 1 - 2^-24.
inline constexpr float U_EDGES[] = {0.0f, 0x1p-149f, 0x1p-24f, 0.5f - 0x1p-25f, 0.5f, 0.5f + 0x1p-24f,
                                    0.75f, ONE_MINUS_EPS};

inline bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// Unit direction at `degrees` from +z, at azimuth `phi` (off the histograms' cell boundaries by default).
// Computed in float on purpose: GCC 12.2 at -O2/-O3 (SLP vectorizer) drops the rounding of float(double) when
// the float is widened again (dvec3(wo) then held the unrounded doubles, and a double reference disagreed with
// the renderer's float wo by up to 1% at 89.9 degrees), so test code must not build a float vec3 from doubles
// and widen it back.
inline glm::vec3 direction_at(float degrees, float phi = 0.7f) {
    const float t = degrees * float(M_PI / 180.0);
    return glm::vec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
}

// ---- Double-precision GGX, written from the papers (not from ggx.glsl) ------------------------------------
namespace ggx {
using glm::dvec3;

// Trowbridge-Reitz distribution (Walter et al. 2007 eq. 33) in its slope form: 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2).
inline double d(dvec3 h, double a) {
    if (!(h.z > 0.0)) return 0.0;
    const double c2 = h.z * h.z, t2 = (h.x * h.x + h.y * h.y) / c2;
    const double k = 1.0 + t2 / (a * a);
    return 1.0 / (M_PI * a * a * c2 * c2 * k * k);
}

// Smith Lambda (Heitz 2014 eq. 72) and the masking of direction w (z = cos theta).
inline double lambda(double cos_theta, double a) {
    const double c2 = cos_theta * cos_theta, tan2 = (1.0 - c2) / c2;
    return 0.5 * (std::sqrt(1.0 + a * a * tan2) - 1.0);
}
inline double g1(double cos_theta, double a) { return 1.0 / (1.0 + lambda(cos_theta, a)); }

// Distribution of normals visible from wo, D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z (Heitz 2018 eq. 1).
inline double vndf(dvec3 wo, dvec3 h, double a) {
    return g1(wo.z, a) * std::max(0.0, glm::dot(wo, h)) * d(h, a) / wo.z;
}

// Solid-angle density of wi = reflect(wo, h) for h ~ D_wo: D_wo(h) / (4 wo.h) (Walter et al. 2007 eq. 14).
inline double vndf_reflection(dvec3 wo, dvec3 wi, double a) {
    if (!(wi.z > 0.0)) return 0.0;
    const dvec3 h = glm::normalize(wo + wi);
    const double wo_h = glm::dot(wo, h);
    return wo_h > 0.0 ? vndf(wo, h, a) / (4.0 * wo_h) : 0.0;
}

inline dvec3 reflect(dvec3 wo, dvec3 h) { return 2.0 * glm::dot(wo, h) * h - wo; }

// The stretch of the lobe (Heitz 2018 sec. 2): s = normalize(h.x / a, h.y / a, h.z) maps the GGX lobe of any
// alpha onto the alpha = 1 lobe, so a histogram or a quadrature in s resolves a lobe of alpha 1e-3 as well as
// one of alpha 1. h = normalize(M s), M = diag(a, a, 1); solid angles transform by
// dw_h / dw_s = det M / |M s|^3 = a^2 / |M s|^3 (the Jacobian of v -> M v / |M v| on the sphere).
inline dvec3 stretched_from_normal(dvec3 h, double a) { return glm::normalize(dvec3(h.x / a, h.y / a, h.z)); }
inline dvec3 normal_from_stretched(dvec3 s, double a) { return glm::normalize(dvec3(a * s.x, a * s.y, s.z)); }
inline double normal_per_stretched_solid_angle(dvec3 s, double a) {
    const double m = std::sqrt(a * a * (s.x * s.x + s.y * s.y) + s.z * s.z);
    return a * a / (m * m * m);
}
}  // namespace ggx

// Cell integrals over a (cos theta, phi) grid of a density that is smooth except that it jumps to (or kinks
// into) 0 across a curve: density(cos, phi, valid) returns the value and sets `valid` (false: 0 there). The
// stretched GGX lobe is such a density, cut where wi reaches the horizon; adaptive 2D Simpson would refine
// along that curve without end. So each cell is integrated by rows: along phi by Gauss-Legendre on the pieces
// between the crossings of the curve (found by bisection, as ggx_albedo_reference.h does), and the rows
// along cos theta by adaptive Simpson to `tolerance` per cell (absolute; a row integral itself jumps where the
// curve runs along phi, near the horizon at grazing wo). `max_depth` stops Simpson chasing float noise.
template <class Density>
std::vector<double> integrate_cut_cells(const HemisphereGrid& grid, const Density& density, double tolerance,
                                        int max_depth = 40) {
    const int n = 6, scan = 4;
    const ggx_albedo::Gauss g = ggx_albedo::gauss_legendre(n);
    auto row = [&](double c, double p0, double dp) {
        c = std::max(c, 1e-7);
        std::vector<double> cuts{p0};
        bool valid, previous;
        density(c, p0, previous);
        for (int m = 1; m <= scan; ++m) {
            density(c, p0 + dp * m / scan, valid);
            if (valid == previous) continue;
            double lo = p0 + dp * (m - 1) / scan, hi = p0 + dp * m / scan;
            for (int it = 0; it < 50; ++it) {
                const double mid = 0.5 * (lo + hi);
                bool v;
                density(c, mid, v);
                (v == previous ? lo : hi) = mid;
            }
            cuts.push_back(0.5 * (lo + hi));
            previous = valid;
        }
        cuts.push_back(p0 + dp);
        double sum_row = 0.0;
        for (size_t q = 0; q + 1 < cuts.size(); ++q)
            for (int l = 0; l < n; ++l)
                sum_row += (cuts[q + 1] - cuts[q]) * g.w[l] *
                           density(c, cuts[q] + (cuts[q + 1] - cuts[q]) * g.x[l], valid);
        return sum_row;
    };
    std::vector<double> out(grid.cells(), 0.0);
    for (int i = 0; i < grid.res_cos; ++i)
        for (int j = 0; j < grid.res_phi; ++j) {
            const double c0 = double(i) / grid.res_cos, c1 = double(i + 1) / grid.res_cos;
            const double p0 = 2.0 * M_PI * j / grid.res_phi, dp = 2.0 * M_PI / grid.res_phi;
            auto simpson = [&](auto&& self, double a, double b, double fa, double fm, double fb, double whole,
                               int depth) -> double {
                const double m = 0.5 * (a + b);
                const double flm = row(0.5 * (a + m), p0, dp), frm = row(0.5 * (m + b), p0, dp);
                const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
                if (depth >= max_depth || std::abs(left + right - whole) <= 15.0 * tolerance)
                    return left + right + (left + right - whole) / 15.0;
                return self(self, a, m, fa, flm, fm, left, depth + 1) + self(self, m, b, fm, frm, fb, right, depth + 1);
            };
            const double fa = row(c0, p0, dp), fm = row(0.5 * (c0 + c1), p0, dp), fb = row(c1, p0, dp);
            out[i * grid.res_phi + j] = simpson(simpson, c0, c1, fa, fm, fb, (c1 - c0) / 6.0 * (fa + 4.0 * fm + fb), 0);
        }
    return out;
}

// The stretched direction at grid coordinates (cos theta, phi).
inline glm::dvec3 grid_direction(double c, double phi) {
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - c * c));
    return glm::dvec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), c);
}

}  // namespace fh::test::stability
