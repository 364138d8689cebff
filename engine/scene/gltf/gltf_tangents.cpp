// MikkTSpace-style tangent generation: weld, per-face u directions, groups of corners around each vertex joined by
// shared edges of the same texture orientation, and the angle-weighted average per group.
#include "scene/gltf/gltf_tangents.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace fh::gltf {
namespace {

// Position, normal and texture coordinates, compared by their bits (MikkTSpace welds equal values).
struct VertexKey {
    float v[8];
    bool operator==(const VertexKey& o) const { return std::memcmp(v, o.v, sizeof v) == 0; }
};

struct VertexKeyHash {
    size_t operator()(const VertexKey& k) const {
        uint64_t h = 1469598103934665603ull;
        const auto* bytes = reinterpret_cast<const unsigned char*>(k.v);
        for (size_t i = 0; i < sizeof k.v; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
        return size_t(h);
    }
};

// One id per distinct (position, normal, uv) among the vertices the triangles use.
std::vector<uint32_t> weld(const std::vector<std::array<uint32_t, 3>>& triangles, const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>& normals, const std::vector<glm::vec4>& uvs) {
    std::vector<uint32_t> welded(positions.size(), UINT32_MAX);
    std::unordered_map<VertexKey, uint32_t, VertexKeyHash> ids;
    for (const auto& tri : triangles)
        for (uint32_t v : tri) {
            if (welded[v] != UINT32_MAX) continue;
            VertexKey key{};
            const float values[8] = {positions[v].x, positions[v].y, positions[v].z, normals[v].x,
                                     normals[v].y,   normals[v].z,   uvs[v].x,       uvs[v].y};
            std::memcpy(key.v, values, sizeof key.v);
            welded[v] = ids.emplace(key, uint32_t(ids.size())).first->second;
        }
    return welded;
}

// A triangle's texture-space u direction (dp/du, unit) and orientation: whether (u, v) turn the same way as the
// triangle's vertex order seen with v up (MikkTSpace's "orientation preserving", its texture coordinates flipped to
// v up as glTF's assets are baked). `valid` is false where the texture coordinates span no area.
struct Face {
    glm::dvec3 u_direction{0.0};
    bool preserving = false;
    bool valid = false;
};

Face face_of(const std::array<uint32_t, 3>& tri, const std::vector<glm::vec3>& positions, const std::vector<glm::vec4>& uvs) {
    Face f;
    const glm::dvec3 d1 = glm::dvec3(positions[tri[1]]) - glm::dvec3(positions[tri[0]]);
    const glm::dvec3 d2 = glm::dvec3(positions[tri[2]]) - glm::dvec3(positions[tri[0]]);
    const glm::dvec2 t1 = glm::dvec2(uvs[tri[1]]) - glm::dvec2(uvs[tri[0]]);
    const glm::dvec2 t2 = glm::dvec2(uvs[tri[2]]) - glm::dvec2(uvs[tri[0]]);
    const double det = t1.x * t2.y - t1.y * t2.x;  // v down; with v up the sign flips
    f.preserving = det < 0.0;
    if (det == 0.0) return f;
    const glm::dvec3 dpdu = (d1 * t2.y - d2 * t1.y) / det;
    const double length = glm::length(dpdu);
    f.valid = length > 0.0 && std::isfinite(length);
    if (f.valid) f.u_direction = dpdu / length;
    return f;
}

// `v` without its component along unit `n`, normalised (zero where nothing is left).
glm::dvec3 project(const glm::dvec3& v, const glm::dvec3& n) {
    const glm::dvec3 p = v - n * glm::dot(n, v);
    const double length = glm::length(p);
    return length > 0.0 && std::isfinite(length) ? p / length : glm::dvec3(0.0);
}

size_t find_root(std::vector<size_t>& parent, size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

}  // namespace

std::vector<std::array<glm::vec4, 3>> generate_tangents(const std::vector<std::array<uint32_t, 3>>& triangles,
                                                        const std::vector<glm::vec3>& positions,
                                                        const std::vector<glm::vec3>& normals,
                                                        const std::vector<glm::vec4>& uvs) {
    std::vector<std::array<glm::vec4, 3>> out(triangles.size(), {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)});
    const std::vector<uint32_t> welded = weld(triangles, positions, normals, uvs);
    std::vector<Face> faces(triangles.size());
    for (size_t f = 0; f < triangles.size(); ++f) faces[f] = face_of(triangles[f], positions, uvs);

    // Corners (3 f + k) sorted by their welded vertex: the corners around each vertex are a run.
    std::vector<uint32_t> corners(3 * triangles.size());
    std::iota(corners.begin(), corners.end(), 0u);
    auto vertex_of = [&](uint32_t c) { return welded[triangles[c / 3][c % 3]]; };
    auto next_of = [&](uint32_t c) { return welded[triangles[c / 3][(c % 3 + 1) % 3]]; };
    auto prev_of = [&](uint32_t c) { return welded[triangles[c / 3][(c % 3 + 2) % 3]]; };
    std::stable_sort(corners.begin(), corners.end(), [&](uint32_t a, uint32_t b) { return vertex_of(a) < vertex_of(b); });

    // Per run of corners around one vertex, reused from run to run: union-find parents, (welded vertex after the
    // corner, index in the run), and each group's sum.
    std::vector<size_t> parent;
    std::vector<std::pair<uint32_t, size_t>> by_next;
    std::vector<glm::dvec3> sums;
    for (size_t begin = 0; begin < corners.size();) {
        size_t end = begin;
        while (end < corners.size() && vertex_of(corners[end]) == vertex_of(corners[begin])) ++end;
        const size_t m = end - begin;
        // Groups: corners whose triangles share an edge through this vertex (wound the same way: one's next vertex is
        // the other's previous) and turn the texture the same way. Triangles without texture-space extent join none.
        parent.resize(m);
        std::iota(parent.begin(), parent.end(), size_t(0));
        by_next.clear();
        for (size_t i = 0; i < m; ++i) by_next.emplace_back(next_of(corners[begin + i]), i);
        std::sort(by_next.begin(), by_next.end());
        for (size_t i = 0; i < m; ++i) {
            const uint32_t a = corners[begin + i];
            if (!faces[a / 3].valid) continue;
            auto it = std::lower_bound(by_next.begin(), by_next.end(), std::make_pair(prev_of(a), size_t(0)));
            for (; it != by_next.end() && it->first == prev_of(a); ++it) {
                const uint32_t b = corners[begin + it->second];
                if (faces[b / 3].valid && faces[b / 3].preserving == faces[a / 3].preserving)
                    parent[find_root(parent, i)] = find_root(parent, it->second);
            }
        }
        // Each group's tangent: its faces' u directions in the normal's plane, weighted by the corner angle.
        sums.assign(m, glm::dvec3(0.0));
        for (size_t i = 0; i < m; ++i) {
            const uint32_t c = corners[begin + i];
            if (!faces[c / 3].valid) continue;
            const std::array<uint32_t, 3>& tri = triangles[c / 3];
            const uint32_t v = tri[c % 3];
            const glm::dvec3 n = glm::dvec3(normals[v]);
            const glm::dvec3 p = glm::dvec3(positions[v]);
            const glm::dvec3 e1 = project(glm::dvec3(positions[tri[(c % 3 + 1) % 3]]) - p, n);
            const glm::dvec3 e2 = project(glm::dvec3(positions[tri[(c % 3 + 2) % 3]]) - p, n);
            const double angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0));
            sums[find_root(parent, i)] += angle * project(faces[c / 3].u_direction, n);
        }
        // A corner of a triangle without extent takes the first group's tangent that has one (MikkTSpace's
        // degenerate triangles take a neighbour's).
        glm::vec4 fallback(0.0f);
        for (int pass = 0; pass < 2; ++pass)
            for (size_t i = 0; i < m; ++i) {
                const uint32_t c = corners[begin + i];
                const bool valid = faces[c / 3].valid;
                if ((pass == 0) != valid) continue;
                glm::vec4 tangent = fallback;
                if (valid) {
                    const glm::dvec3 sum = sums[find_root(parent, i)];
                    const double length = glm::length(sum);
                    tangent = length > 0.0 && std::isfinite(length)
                                  ? glm::vec4(glm::vec3(sum / length), faces[c / 3].preserving ? 1.0f : -1.0f)
                                  : glm::vec4(0.0f);
                    if (fallback.w == 0.0f) fallback = tangent;
                }
                out[c / 3][c % 3] = tangent;
            }
        begin = end;
    }
    return out;
}

}  // namespace fh::gltf
