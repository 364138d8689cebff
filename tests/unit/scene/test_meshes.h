// Test helper: deterministic triangle sets (random soups, grids, spheres) as flat position arrays.
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace fh::test {

// Uniform floats in [0, 1) from the mt19937 bit stream (portable, unlike std::uniform_real_distribution).
struct Rng {
    std::mt19937 engine;
    explicit Rng(uint32_t seed) : engine(seed) {}
    float uniform() { return float(engine() >> 8) * 0x1p-24f; }
    glm::vec3 uniform3(float lo, float hi) {
        const float x = uniform(), y = uniform(), z = uniform();
        return glm::vec3(lo) + (hi - lo) * glm::vec3(x, y, z);
    }
};

inline std::vector<glm::vec3> make_random_soup(size_t count, uint32_t seed, float extent = 10.0f, float size = 1.0f) {
    Rng rng(seed);
    std::vector<glm::vec3> p;
    p.reserve(3 * count);
    for (size_t i = 0; i < count; ++i) {
        const glm::vec3 c = rng.uniform3(-extent, extent);
        for (int k = 0; k < 3; ++k) p.push_back(c + rng.uniform3(-size, size));
    }
    return p;
}

// An indexed mesh expanded to flat triangles; the vertex array is kept for aiming rays at vertices.
struct Mesh {
    std::vector<glm::vec3> vertices;
    std::vector<uint32_t> indices;  // 3 per triangle
    std::vector<glm::vec3> flatten() const {
        std::vector<glm::vec3> p;
        for (uint32_t i : indices) p.push_back(vertices[i]);
        return p;
    }
};

// n x n quads over [-1, 1]^2 in the z = 0 plane (bumped in z by `bump` * a smooth function), 2 triangles each.
inline Mesh make_grid(uint32_t n, float bump = 0.0f) {
    Mesh m;
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(n), y = -1.0f + 2.0f * float(j) / float(n);
            m.vertices.push_back({x, y, bump * std::sin(3.0f * x) * std::cos(2.0f * y)});
        }
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            // Alternate the diagonal so vertices have both valence 4 and 8.
            if ((i + j) % 2 == 0) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
            else m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    return m;
}

// A closed UV sphere: `rings` latitude bands, `segments` longitudes, poles shared.
inline Mesh make_sphere(glm::vec3 center, float radius, uint32_t rings, uint32_t segments) {
    Mesh m;
    const float pi = 3.14159265358979f;
    m.vertices.push_back(center + glm::vec3(0, 0, radius));
    for (uint32_t r = 1; r < rings; ++r) {
        const float theta = pi * float(r) / float(rings);
        for (uint32_t s = 0; s < segments; ++s) {
            const float phi = 2.0f * pi * float(s) / float(segments);
            m.vertices.push_back(center + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                             std::sin(theta) * std::sin(phi), std::cos(theta)));
        }
    }
    m.vertices.push_back(center + glm::vec3(0, 0, -radius));
    const uint32_t south = uint32_t(m.vertices.size() - 1);
    auto ring_vertex = [&](uint32_t r, uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
    for (uint32_t s = 0; s < segments; ++s) {
        m.indices.insert(m.indices.end(), {0, ring_vertex(1, s), ring_vertex(1, s + 1)});
        for (uint32_t r = 1; r + 1 < rings; ++r)
            m.indices.insert(m.indices.end(), {ring_vertex(r, s), ring_vertex(r + 1, s), ring_vertex(r + 1, s + 1),
                                               ring_vertex(r, s), ring_vertex(r + 1, s + 1), ring_vertex(r, s + 1)});
        m.indices.insert(m.indices.end(), {ring_vertex(rings - 1, s), south, ring_vertex(rings - 1, s + 1)});
    }
    return m;
}

// A scene of flat-shaded triangles (3 positions each) that all use one material.
inline Scene make_single_material_scene(const std::vector<glm::vec3>& positions, const gpu::Material& material) {
    Scene scene;
    scene.positions = positions;
    scene.normals.assign(positions.size(), glm::vec3(0.0f));
    scene.triangle_material.assign(positions.size() / 3, 0);
    scene.triangle_has_normals.assign(positions.size() / 3, 0);
    scene.materials.push_back(material);
    return scene;
}

}  // namespace fh::test
