// Goodness-of-fit machinery for the sampling tests, after Mitsuba 3's ChiSquareTest: histogram samples on a
// grid, integrate the claimed pdf over every cell, pool sparse cells, and turn Pearson's statistic into a
// p-value with the regularized incomplete gamma function. Also the quadrature the BSDF tests share.
#pragma once
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace fh::test {

// Regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): series for P when
// x < a + 1, Lentz's continued fraction for Q otherwise (Numerical Recipes 3rd ed., sec. 6.2).
inline double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double ap = a, term = 1.0 / a, sum = term;
        for (int n = 0; n < 100000 && std::abs(term) > std::abs(sum) * 1e-16; ++n) {
            ap += 1.0;
            term *= x / ap;
            sum += term;
        }
        return std::max(0.0, 1.0 - sum * std::exp(log_prefix));
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(log_prefix) * h;
}

// Significance level of each of `test_count` tests so that the whole suite fails by chance with
// probability 0.01 (Sidak correction, as Mitsuba 3's tests do).
inline double corrected_significance(int test_count) {
    return 1.0 - std::pow(1.0 - 0.01, 1.0 / test_count);
}

// Every chi-square test in tests/unit (test_bsdf_chi_square: 60, test_bsdf_glass: 36, test_bsdf_clearcoat: 24,
// test_bsdf_sheen: 24, test_bsdf_diffuse_transmission: 12, test_bsdf_anisotropy: 15, test_sampling: 7, test_light_tree: 18): keep it up
// to date when adding one.
inline constexpr int UNIT_CHI_SQUARE_TESTS = 206;

struct ChiSquareResult {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 0.0;
    std::string error;  // non-empty: samples where the pdf claims probability 0, or too few cells
};

// Pearson's test of observed counts against expected counts. Cells are visited by increasing expectation;
// cells expecting fewer than `min_expected` are pooled until the pool reaches it (Mitsuba 3's chi2_test).
inline ChiSquareResult chi_square_test(const std::vector<double>& observed, const std::vector<double>& expected,
                                       double min_expected = 5.0) {
    ChiSquareResult r;
    std::vector<size_t> order(expected.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
    double pool_obs = 0.0, pool_exp = 0.0;
    for (size_t i : order) {
        if (expected[i] <= 0.0 && observed[i] > 0.0) {
            std::ostringstream s;
            s << "cell " << i << " got " << observed[i] << " samples but the pdf integrates to " << expected[i];
            r.error = s.str();
            return r;
        }
        if (expected[i] < min_expected || (pool_exp > 0.0 && pool_exp < min_expected)) {
            pool_obs += observed[i];
            pool_exp += expected[i];
            continue;
        }
        const double d = observed[i] - expected[i];
        r.statistic += d * d / expected[i];
        r.dof += 1;
    }
    if (pool_exp > 0.0) {
        const double d = pool_obs - pool_exp;
        r.statistic += d * d / pool_exp;
        r.dof += 1;
    }
    r.dof -= 1;
    if (r.dof < 1) {
        r.error = "fewer than two cells after pooling";
        return r;
    }
    r.p_value = gamma_q(0.5 * r.dof, 0.5 * r.statistic);
    return r;
}

// Anisotropic adaptive Simpson cubature over [x0,x1]x[y0,y1]: the 3x3-point rule is compared with the
// rules on the two halves in x and on the two halves in y; the cell is split along the axis whose halves
// disagree most (a lobe varying along one axis only is refined along that axis only), until the
// disagreement is below `tol` (absolute, halved per split) or 3e-4 of the node's integral.
template <class F>
double integrate_adaptive(const F& f, double x0, double x1, double y0, double y1, double tol, long& budget,
                          int depth = 0) {
    budget -= 21;
    double v[5][5];
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            if (i % 2 == 0 || j % 2 == 0) v[i][j] = f(x0 + (x1 - x0) * i / 4.0, y0 + (y1 - y0) * j / 4.0);
    const double w[3] = {1.0, 4.0, 1.0};
    double coarse = 0.0, fine_x = 0.0, fine_y = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            coarse += w[i] * w[j] * v[2 * i][2 * j];
            fine_x += w[i] * w[j] * (v[i][2 * j] + v[2 + i][2 * j]);
            fine_y += w[i] * w[j] * (v[2 * i][j] + v[2 * i][2 + j]);
        }
    const double area = (x1 - x0) * (y1 - y0);
    coarse *= area / 36.0;
    fine_x *= area / 72.0;
    fine_y *= area / 72.0;
    const double err_x = std::abs(fine_x - coarse), err_y = std::abs(fine_y - coarse);
    // Besides the absolute tolerance, a relative one per node, and an evaluation budget: the integrand is a
    // float computation whose rounding noise (up to ~1e-3 relative at the peak of a sharp GGX lobe seen at
    // grazing angles, where h.xy / alpha loses digits) would otherwise keep refining forever.
    // Accepted nodes return the finer rule plus its Richardson correction (Simpson's error is O(h^4) per axis).
    const double fine = err_x > err_y ? fine_x + (fine_x - coarse) / 15.0 : fine_y + (fine_y - coarse) / 15.0;
    if (std::max(err_x, err_y) <= std::max(15.0 * tol, 3e-4 * std::abs(fine)) || depth >= 40 || budget <= 0)
        return fine;
    const double t = 0.5 * tol;
    if (err_x >= err_y) {
        const double xm = 0.5 * (x0 + x1);
        return integrate_adaptive(f, x0, xm, y0, y1, t, budget, depth + 1) +
               integrate_adaptive(f, xm, x1, y0, y1, t, budget, depth + 1);
    }
    const double ym = 0.5 * (y0 + y1);
    return integrate_adaptive(f, x0, x1, y0, ym, t, budget, depth + 1) +
           integrate_adaptive(f, x0, x1, ym, y1, t, budget, depth + 1);
}

// Integral of f over one cell, first split at a known peak (px, py) when it lies inside, so that the peak
// becomes a corner that every Simpson rule evaluates: a lobe much narrower than the cell is never missed.
template <class F>
double integrate_cell(const F& f, double x0, double x1, double y0, double y1, double px, double py, double tol) {
    std::vector<double> xs{x0}, ys{y0};
    if (px > x0 && px < x1) xs.push_back(px);
    if (py > y0 && py < y1) ys.push_back(py);
    xs.push_back(x1);
    ys.push_back(y1);
    double sum = 0.0;
    for (size_t i = 0; i + 1 < xs.size(); ++i)
        for (size_t j = 0; j + 1 < ys.size(); ++j) {
            long budget = 2000000;  // evaluations per piece: a safety net against endless refinement of noise
            sum += integrate_adaptive(f, xs[i], xs[i + 1], ys[j], ys[j + 1], tol, budget);
        }
    return sum;
}

// Hemisphere grid in (cos theta, phi): dw = dcos dphi, so cell integrals of a solid-angle density are plain
// 2D integrals. Directions below cos = 1e-7 are evaluated at 1e-7 (the density's continuous extension).
struct HemisphereGrid {
    int res_cos = 64;
    int res_phi = 128;

    int cells() const { return res_cos * res_phi; }
    int cell_of(double x, double y, double z) const {
        double phi = std::atan2(y, x);
        if (phi < 0.0) phi += 2.0 * M_PI;
        const int i = std::clamp(int(z * res_cos), 0, res_cos - 1);
        const int j = std::clamp(int(phi / (2.0 * M_PI) * res_phi), 0, res_phi - 1);
        return i * res_phi + j;
    }
    // Integrals of density(x, y, z) over every cell; (peak_x, peak_y, peak_z) is a direction where it peaks.
    template <class D>
    std::vector<double> integrate(const D& density, double peak_x, double peak_y, double peak_z, double rel_tol,
                                  double abs_tol) const {
        auto f = [&](double c, double phi) {
            c = std::max(c, 1e-7);
            const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
            return density(s * std::cos(phi), s * std::sin(phi), c);
        };
        double peak_phi = std::atan2(peak_y, peak_x);
        if (peak_phi < 0.0) peak_phi += 2.0 * M_PI;
        std::vector<double> out(cells());
        for (int i = 0; i < res_cos; ++i)
            for (int j = 0; j < res_phi; ++j) {
                const double c0 = double(i) / res_cos, c1 = double(i + 1) / res_cos;
                const double p0 = 2.0 * M_PI * j / res_phi, p1 = 2.0 * M_PI * (j + 1) / res_phi;
                const double guess = std::abs(f(0.5 * (c0 + c1), 0.5 * (p0 + p1))) * (c1 - c0) * (p1 - p0);
                out[i * res_phi + j] = integrate_cell(f, c0, c1, p0, p1, peak_z, peak_phi, std::max(rel_tol * guess, abs_tol));
            }
        return out;
    }
};

}  // namespace fh::test
