// Double-precision reference for shaders/lib/tables/sheen_albedo_table.glsl: the directional albedo
//   E(mu, roughness) = int D(h) V(wo, wi) cos(theta_i) dwi
// of KHR_materials_sheen's Charlie lobe with sheenColor 1 (shaders/lib/bsdf/sheen.glsl has the lobe).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "ggx_albedo_reference.h"  // gauss_legendre

namespace fh::test::sheen_albedo {

// Cosines below this read as it (sheen.glsl SHEEN_MIN_COSINE, the table's first non-zero mu, (1 / 31)^3): the
// albedo grows without bound as mu -> 0, because the fitted Lambda grows more slowly than 1 / mu.
constexpr double MIN_COSINE = 1.0 / 29791.0;

inline double fit_lambda(double x, double alpha) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    auto mix = [t](double a, double b) { return a + (b - a) * t; };
    return mix(21.5473, 25.3245) / (1.0 + mix(3.82987, 3.32435) * std::pow(x, mix(0.19823, 0.16801))) +
           mix(-1.97760, -1.27393) * x + mix(-4.32054, -4.85967);
}

inline double lambda(double mu, double alpha) {
    return mu < 0.5 ? std::exp(fit_lambda(mu, alpha)) : std::exp(2.0 * fit_lambda(0.5, alpha) - fit_lambda(1.0 - mu, alpha));
}

inline double charlie_d(double cos_h, double alpha) {
    return (2.0 + 1.0 / alpha) * std::pow(std::max(1.0 - cos_h * cos_h, 0.0), 0.5 / alpha) / (2.0 * M_PI);
}

// E by quadrature over the half vector h = (sin cos phi, sin sin phi, t) (dwi = 4 (wo.h) dh): for each t, the
// half vectors that reflect wo above the surface are exactly cos phi > c(t) (below), so the phi integral runs
// over a smooth integrand; t is split where c crosses -1 and 1 (the phi range's ends) and at D's width.
// Agrees with brute-force quadrature over wi to 1e-4.
inline double albedo(double mu, double roughness, int points = 24, int panels = 24) {
    const ggx_albedo::Gauss g = ggx_albedo::gauss_legendre(points);
    mu = std::max(mu, MIN_COSINE);
    const double alpha = roughness * roughness, so = std::sqrt(1.0 - mu * mu);
    auto c_of = [&](double t) {  // wi.z = 2 (wo.h) t - mu > 0  <=>  cos phi > c
        const double den = so * std::sqrt(std::max(1.0 - t * t, 0.0)), num = mu / (2.0 * t) - mu * t;
        return den > 0.0 ? num / den : (num < 0.0 ? -2.0 : 2.0);
    };
    auto key = [&](double t) { const double c = c_of(t); return c >= 1.0 ? 0 : (c <= -1.0 ? 2 : 1); };
    std::vector<double> breaks{0.0, std::min(1.0, 10.0 * std::sqrt(alpha))};
    for (int k = 1, prev = key(1e-9); k <= 2048; ++k) {
        const double t = k / 2048.0;
        const int cur = key(t);
        if (cur == prev) continue;
        double lo = (k - 1) / 2048.0, hi = t;
        for (int it = 0; it < 60; ++it) {
            const double m = 0.5 * (lo + hi);
            (key(m) == prev ? lo : hi) = m;
        }
        breaks.push_back(0.5 * (lo + hi));
        prev = cur;
    }
    breaks.push_back(1.0);
    std::sort(breaks.begin(), breaks.end());
    const double lambda_o = lambda(mu, alpha);
    double sum = 0.0;
    for (size_t s = 0; s + 1 < breaks.size(); ++s) {
        const double len = breaks[s + 1] - breaks[s];
        if (!(len > 0.0)) continue;
        for (int p = 0; p < panels; ++p)
            for (int i = 0; i < points; ++i) {
                const double t = breaks[s] + len * (p + g.x[i]) / panels, wt = len * g.w[i] / panels;
                const double phi_max = std::acos(std::clamp(c_of(t), -1.0, 1.0));
                if (!(phi_max > 0.0)) continue;
                const double d = charlie_d(t, alpha), sh = std::sqrt(std::max(1.0 - t * t, 0.0));
                for (int j = 0; j < points; ++j) {
                    const double oh = so * sh * std::cos(phi_max * g.x[j]) + mu * t, mu_i = 2.0 * oh * t - mu;
                    if (!(mu_i > 0.0)) continue;
                    // D G2 / (4 mu) times the Jacobian 4 (wo.h), both signs of phi.
                    sum += 2.0 * wt * phi_max * g.w[j] * d / (1.0 + lambda_o + lambda(std::max(mu_i, MIN_COSINE), alpha)) * oh / mu;
                }
            }
    }
    return sum;
}

}  // namespace fh::test::sheen_albedo
