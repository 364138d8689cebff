// The BSDF test executables' shared setup: shaders/lib/bsdf.glsl compiled as C++ (in fh::glsl) and the
// materials, directions and quadrature the tests share. Include once per executable (the .glsl functions
// are not inline).
#pragma once
#include <cmath>
#include <numeric>
#include <vector>

#include "chi_square.h"
#include "shared/layout.h"
#include "lib/cpp_compat.h"
namespace fh::glsl {
#include "lib/bsdf.glsl"
}  // namespace fh::glsl

namespace fh::test {
using namespace fh::glsl;

inline const float ONE_MINUS_EPS = 1.0f - 1.0f / 16777216.0f;  // largest float the RNG returns
inline const float ROUGHNESSES[] = {0.05f, 0.2f, 0.5f, 1.0f};
inline const float INCIDENCES[] = {0.0f, 30.0f, 60.0f, 80.0f, 89.0f};  // degrees
enum Kind { DIELECTRIC, METAL, HALF_METAL, KIND_COUNT };
inline const char* const KIND_NAMES[] = {"dielectric", "metal", "halfmetal"};

inline fh::gpu::Material make_material(vec3 base, float metallic, float roughness, float specular = 1.0f,
                                       vec3 specular_color = vec3(1.0f), float ior = 1.5f) {
    fh::gpu::Material m{};
    m.base_color = vec4(base, 1.0f);
    m.specular_color = vec4(specular_color, specular);
    m.metallic = metallic;
    m.roughness = roughness;
    m.ior = ior;
    m.base_color_texture = m.metallic_roughness_texture = m.normal_texture = m.emissive_texture = 0xffffffffu;
    return m;
}

inline BsdfParams make_case(Kind kind, float roughness) {
    switch (kind) {
        case DIELECTRIC: return make_bsdf_params(make_material(vec3(0.7f, 0.5f, 0.3f), 0.0f, roughness));
        case METAL: return make_bsdf_params(make_material(vec3(0.9f, 0.6f, 0.4f), 1.0f, roughness));
        default: return make_bsdf_params(make_material(vec3(0.5f, 0.8f, 0.6f), 0.5f, roughness));
    }
}

// Outgoing direction at `degrees` from the normal, at an azimuth off the histogram's cell boundaries.
inline vec3 outgoing(float degrees) {
    const float t = glm::radians(degrees), phi = 0.7f;
    return vec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
}

inline bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Integrals of a density over the grid cells, split at the mirror direction where the GGX lobe peaks.
template <class D>
std::vector<double> integrate_cells(const HemisphereGrid& grid, vec3 wo, const D& density) {
    return grid.integrate(
        [&](double x, double y, double z) { return density(vec3(float(x), float(y), float(z))); }, -wo.x, -wo.y,
        wo.z, 1e-5, 1e-11);
}

inline double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// Quadrature of a directional function over the hemisphere (32 x 64 cells, split at the mirror direction).
template <class D>
double integrate_hemisphere(vec3 wo, const D& density) {
    HemisphereGrid grid;
    grid.res_cos = 32;
    grid.res_phi = 64;
    return sum(integrate_cells(grid, wo, density));
}

}  // namespace fh::test
