// Test helper for the GPU stability cases: double-precision random numbers and geometry (icosphere, meshes
// placed far from the origin or scaled down), rounded to float only at the end, and a double reference
// ray/triangle test.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "../../unit/scene/test_meshes.h"

namespace fh::test {

// Uniform doubles in [0, 1) from the mt19937_64 bit stream (portable, unlike std::uniform_real_distribution).
struct Rng64 {
    std::mt19937_64 engine;
    explicit Rng64(uint64_t seed) : engine(seed) {}
    double uniform() { return double(engine() >> 11) * 0x1p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniform on the unit sphere (Marsaglia's rejection: no trigonometry, no pole clustering).
    glm::dvec3 unit_vector() {
        while (true) {
            const glm::dvec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            const double l2 = glm::dot(v, v);
            if (l2 > 1e-6 && l2 <= 1.0) return v / std::sqrt(l2);
        }
    }
    // Uniform in the ball of radius r.
    glm::dvec3 in_ball(double r) { return r * std::cbrt(uniform()) * unit_vector(); }
};

// A closed icosphere: the icosahedron with each face split into 4 `subdivisions` times, vertices pushed to the
// sphere. Shared vertices are stored once, so every shared edge has bit-identical endpoints in every triangle.
// Computed in double and rounded to float once: far from the origin the rounding jitters the vertices, but
// the mesh stays closed. 20 * 4^subdivisions triangles.
inline Mesh make_icosphere(glm::dvec3 centre, double radius, int subdivisions) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (glm::dvec3& p : v) p = glm::normalize(p);
    std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1,  0, 1, 7,  0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                               11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2,  3, 2, 6, 3, 6, 8,
                               3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
        auto mid = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, added] = midpoint.try_emplace(key, uint32_t(v.size()));
            if (added) v.push_back(glm::normalize(v[a] + v[b]));
            return it->second;
        };
        std::vector<uint32_t> next;
        for (size_t t = 0; t < f.size(); t += 3) {
            const uint32_t a = f[t], b = f[t + 1], c = f[t + 2];
            const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(next);
    }
    Mesh m;
    for (const glm::dvec3& p : v) m.vertices.push_back(glm::vec3(centre + radius * p));
    m.indices = std::move(f);
    return m;
}

// A mesh moved to `centre` and scaled by `scale` in double precision, then rounded to float.
inline Mesh place_mesh(const Mesh& local, glm::dvec3 centre, double scale) {
    Mesh m = local;
    for (glm::vec3& p : m.vertices) p = glm::vec3(centre + scale * glm::dvec3(p));
    return m;
}

struct ReferenceHit {
    double t = std::numeric_limits<double>::infinity();
    uint32_t triangle = 0xffffffffu;
    double edge_distance = 1.0;  // smallest barycentric coordinate at the hit (0 = on an edge)
};

// Moller & Trumbore (1997) in double precision with inclusive edges, on the float inputs taken as exact.
inline ReferenceHit intersect_reference(glm::dvec3 o, glm::dvec3 d, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2) {
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, q = glm::cross(d, e2);
    const double det = glm::dot(e1, q);
    ReferenceHit none;
    if (det == 0.0) return none;
    const glm::dvec3 s = o - p0, r = glm::cross(s, e1);
    const double b1 = glm::dot(s, q) / det, b2 = glm::dot(d, r) / det, t = glm::dot(e2, r) / det;
    if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0) return none;
    return {t, 0, std::min({b1, b2, 1 - b1 - b2})};
}

// The smallest barycentric coordinate where the line o + t d meets the triangle's plane, without rejection:
// negative outside, 0 on an edge; -infinity when the line is parallel to the plane.
inline double signed_edge_distance(glm::dvec3 o, glm::dvec3 d, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2) {
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, q = glm::cross(d, e2);
    const double det = glm::dot(e1, q);
    if (det == 0.0) return -std::numeric_limits<double>::infinity();
    const glm::dvec3 s = o - p0, r = glm::cross(s, e1);
    const double b1 = glm::dot(s, q) / det, b2 = glm::dot(d, r) / det;
    return std::min({b1, b2, 1 - b1 - b2});
}

// The closest hit over every triangle of a flat position array (brute force).
inline ReferenceHit trace_reference(const std::vector<glm::vec3>& p, glm::vec3 origin, glm::vec3 dir) {
    ReferenceHit best;
    for (uint32_t tri = 0; tri < p.size() / 3; ++tri) {
        ReferenceHit h = intersect_reference(glm::dvec3(origin), glm::dvec3(dir), glm::dvec3(p[3 * tri]),
                                             glm::dvec3(p[3 * tri + 1]), glm::dvec3(p[3 * tri + 2]));
        if (h.t < best.t) best = {h.t, tri, h.edge_distance};
    }
    return best;
}

}  // namespace fh::test
