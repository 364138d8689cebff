// A Schlick-shaped envelope of the thin film's Fresnel, searched on a grid of angles and optical path differences.
#include "scene/thin_film_bound.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "lib/core/cpp_compat.h"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"  // the parts of the BSDF this file does not call
namespace fh::glsl {
namespace {  // internal linkage: test executables link this beside their own copy of the shared libraries
#include "lib/bsdf/bsdf.glsl"
}  // namespace
}  // namespace fh::glsl
#pragma GCC diagnostic pop

namespace fh {
namespace {

// A margin on top of the largest ratio found: the grid's gaps and float rounding near grazing angles.
constexpr double ENVELOPE_MARGIN = 0.005;
// Angles: c = (k / N)^2, dense near grazing where the ratio (F - w) / (1 - w) converges slowly.
constexpr int ANGLE_STEPS = 256;
// Optical path differences: a step of at most this (nm); past OPD_CUTOFF the interference terms are below 1e-7
// (exp(-(2 pi OPD 1e-9)^2 4.33e9) at 10 um) and F no longer depends on the thickness.
constexpr double OPD_STEP = 5.0;
constexpr double OPD_CUTOFF = 10000.0;
// The envelope's weight at grazing incidence, b: searched over [1, B_LARGEST] in B_STEPS steps.
constexpr double B_LARGEST = 4.0;
constexpr int B_STEPS = 300;

// Calls visit(k, c, F_film(c, d)) over the grid of angles and thicknesses, `refine` times finer than the bound's.
template <class Visit>
void visit_film(const gpu::Material& material, const gpu::MaterialLayers& layers, int refine, Visit visit) {
    const glm::vec3 f0 = glsl::make_bsdf_params(material).f0_dielectric;  // the film's base, as the shader's
    const float ior = layers.iridescence_ior;
    const bool textured = layers.iridescence_thickness_texture != gpu::INVALID_INDEX;
    const double thickest = layers.iridescence_thickness_max;
    const double thinnest = textured ? std::min<double>(layers.iridescence_thickness_min, thickest) : thickest;
    const double top = textured ? std::max<double>(layers.iridescence_thickness_min, thickest) : thickest;
    const int angles = ANGLE_STEPS * refine;
    for (int k = 1; k <= angles; ++k) {
        const double t = double(k) / angles;
        const float c = float(t * t);
        auto at = [&](double d) { visit(k, c, glsl::eval_thin_film_fresnel(c, float(d), ior, f0)); };
        // The film fades in over its first 0.03 nm (its index goes from the outside's to its own).
        const double fade = glsl::THIN_FILM_FADE_THICKNESS;
        if (thinnest < fade)
            for (int j = 0; j <= 4 * refine; ++j) at(std::min(thinnest + (fade - thinnest) * j / (4.0 * refine), top));
        // Past the fade, F depends on the thickness through OPD = 2 n d cos theta_2 only.
        const double sin2 = (1.0 - double(c) * c) / (double(ior) * ior);
        const double opd_per_nm = 2.0 * ior * std::sqrt(std::max(1.0 - sin2, 0.0));
        const double low = std::max(thinnest, fade);
        if (low > top) continue;
        const double high = std::min(top, std::max(low, OPD_CUTOFF / std::max(opd_per_nm, 1.0e-12)));
        const int steps = int(std::ceil((high - low) * opd_per_nm / (OPD_STEP / refine)));
        for (int j = 0; j <= steps; ++j) at(steps == 0 ? low : low + (high - low) * j / steps);
        if (high < top) at(top);
    }
}

// The grid's largest F over the thicknesses at each angle c_k = (k / ANGLE_STEPS)^2 (refine 1), k = 1 ...
std::vector<float> find_largest_film_fresnel(const gpu::Material& material, const gpu::MaterialLayers& layers) {
    std::vector<float> top(ANGLE_STEPS, 0.0f);
    visit_film(material, layers, 1, [&](int k, float, glm::vec3 f) {
        top[size_t(k - 1)] = std::max({top[size_t(k - 1)], f.x, f.y, f.z});
    });
    return top;
}

}  // namespace

FilmFresnelBound bound_thin_film_fresnel(const gpu::Material& material, const gpu::MaterialLayers& layers) {
    FilmFresnelBound best;
    if (!(layers.iridescence > 0.0f)) return best;
    const std::vector<float> top = find_largest_film_fresnel(material, layers);
    double best_cost = HUGE_VAL;
    for (int j = 0; j <= B_STEPS; ++j) {
        const double b = 1.0 + (B_LARGEST - 1.0) * j / B_STEPS;
        double a = 0.0;
        for (int k = 1; k <= ANGLE_STEPS; ++k) {
            const double t = double(k) / ANGLE_STEPS, m = 1.0 - t * t, w = m * m * m * m * m;
            if (w < 1.0) a = std::max(a, (top[size_t(k - 1)] - b * w) / (1.0 - w));
        }
        const double cost = 20.0 * a + b;  // a A_avg + b B_avg of a mirror, times 21
        if (cost < best_cost) {
            best_cost = cost;
            best.a = float(std::clamp(a + ENVELOPE_MARGIN, 0.0, 1.0));
            best.b = float(b + ENVELOPE_MARGIN);
        }
    }
    return best;
}

float measure_thin_film_excess(const gpu::Material& material, const gpu::MaterialLayers& layers, FilmFresnelBound bound,
                               int refine) {
    double excess = -1.0;
    visit_film(material, layers, refine, [&](int, float c, glm::vec3 f) {
        const double m = 1.0 - c, w = m * m * m * m * m;
        excess = std::max(excess, double(std::max({f.x, f.y, f.z})) - (bound.a * (1.0 - w) + bound.b * w));
    });
    return float(excess);
}

}  // namespace fh
