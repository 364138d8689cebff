// Double-precision reference for shaders/lib/tables/ggx_albedo_table.glsl: the directional albedo of the GGX
// specular lobe (height-correlated Smith) split by Schlick's weight s = (1 - wo.h)^5 into
//   A(mu, alpha) = int D V cos (1 - s) dwi   and   B(mu, alpha) = int D V cos s dwi,
// so that a lobe with F = f0 + (f90 - f0) s has albedo f0 A + f90 B; and the table built from them.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

namespace fh::test::ggx_albedo {

struct Gauss {
    std::vector<double> x, w;  // nodes and weights on [0, 1]
};

inline Gauss gauss_legendre(int n) {
    Gauss g;
    g.x.resize(n);
    g.w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; ++j) {
                const double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            dp = n * (z * p1 - p2) / (z * z - 1.0);
            const double step = p1 / dp;
            z -= step;
            if (std::abs(step) < 1e-15) break;
        }
        g.x[i] = 0.5 * (1.0 - z);
        g.w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
    return g;
}

// Smith's Lambda for GGX (Heitz 2014 eq. 72).
inline double smith_lambda(double mu, double alpha) {
    return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * (1.0 - mu * mu) / (mu * mu)));
}

// One visible normal (Dupuy & Benyoub 2023, as ggx.glsl) for wo = (sqrt(1 - mu^2), 0, mu), at cap
// coordinates (phi, z). Returns false when the reflected direction is below the horizon; otherwise the
// estimator weight G2 / G1 (height-correlated, Heitz 2014 eq. 99 over eq. 43) and s = (1 - wo.h)^5.
inline bool eval_visible_normal(double mu, double alpha, double phi, double z, double& weight, double& s) {
    const double wox = std::sqrt(std::max(0.0, 1.0 - mu * mu)), woz = mu;
    const double stretched = std::sqrt(alpha * alpha * wox * wox + woz * woz);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - z * z));
    double hx = alpha * (sin_t * std::cos(phi) + alpha * wox / stretched), hy = alpha * sin_t * std::sin(phi),
           hz = std::max(z + woz / stretched, 0.0);
    const double len = std::sqrt(hx * hx + hy * hy + hz * hz);
    if (!(len > 0.0)) return false;
    hx /= len;
    hy /= len;
    hz /= len;
    const double vh = wox * hx + woz * hz, wiz = 2.0 * vh * hz - woz;
    if (!(wiz > 0.0)) return false;
    const double lo = smith_lambda(mu, alpha), li = smith_lambda(wiz, alpha);
    weight = (1.0 + lo) / (1.0 + lo + li);
    const double m = std::clamp(1.0 - vh, 0.0, 1.0);
    s = m * m * m * m * m;
    return true;
}

struct Albedo {
    double a = 0.0, b = 0.0;
};

// A and B at (mu, alpha) by product Gauss-Legendre quadrature over the visible-normal sample space (where
// the integrand is the bounded weight G2 / G1), with the domain split where the reflected direction crosses
// the horizon: along z where that happens at phi = 0 or pi, along phi (bisection) within each z line.
// Agrees with a quadrature of 4x the points to about 1e-5 (3e-5 at worst, for alpha ~ 0.01).
inline Albedo albedo(double mu, double alpha, int points = 24, int panels = 16) {
    const Gauss g = gauss_legendre(points);
    mu = std::max(mu, 1e-7);
    const double wox = std::sqrt(1.0 - mu * mu);
    const double z_min = -mu / std::sqrt(alpha * alpha * wox * wox + mu * mu);  // cap: z in [z_min, 1]
    double weight, s;
    auto valid = [&](double phi, double t) { return eval_visible_normal(mu, alpha, phi, z_min + (1.0 - z_min) * t, weight, s); };
    auto bisect = [](double lo, double hi, auto&& same_as_lo) {
        for (int it = 0; it < 60; ++it) {
            const double m = 0.5 * (lo + hi);
            (same_as_lo(m) ? lo : hi) = m;
        }
        return 0.5 * (lo + hi);
    };
    std::vector<double> t_breaks{0.0};
    auto key = [&](double t) { return int(valid(0.0, t)) + 2 * int(valid(M_PI, t)); };
    for (int k = 1, prev = key(0.0); k <= 256; ++k) {
        const int cur = key(k / 256.0);
        if (cur == prev) continue;
        t_breaks.push_back(bisect((k - 1) / 256.0, k / 256.0, [&](double t) { return key(t) == prev; }));
        prev = cur;
    }
    t_breaks.push_back(1.0);
    Albedo r;
    for (size_t seg = 0; seg + 1 < t_breaks.size(); ++seg)
        for (int p = 0; p < panels; ++p)
            for (int i = 0; i < points; ++i) {
                const double len = t_breaks[seg + 1] - t_breaks[seg];
                const double t = t_breaks[seg] + len * (p + g.x[i]) / panels, wt = len * g.w[i] / panels;
                std::vector<double> cuts{0.0};  // phi in [0, pi]: the integrand is even in phi
                bool prev = valid(0.0, t);
                for (int k = 1; k <= 48; ++k) {
                    const bool cur = valid(M_PI * k / 48, t);
                    if (cur == prev) continue;
                    cuts.push_back(bisect(M_PI * (k - 1) / 48, M_PI * k / 48, [&](double phi) { return valid(phi, t) == prev; }));
                    prev = cur;
                }
                cuts.push_back(M_PI);
                for (size_t c = 0; c + 1 < cuts.size(); ++c)
                    for (int j = 0; j < points; ++j) {
                        if (!valid(cuts[c] + (cuts[c + 1] - cuts[c]) * g.x[j], t)) continue;
                        const double q = wt * g.w[j] * (cuts[c + 1] - cuts[c]) / M_PI * weight;
                        r.a += q * (1.0 - s);
                        r.b += q * s;
                    }
            }
    return r;
}

}  // namespace fh::test::ggx_albedo
