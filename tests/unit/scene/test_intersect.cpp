// intersect.glsl compiled as C++: single-triangle cases, then a wide-BVH traversal that must agree with
// brute force (float and double precision) and must not leak through shared vertices and edges (watertight).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/geometry/intersect.glsl"
}
#include "scene/bvh/bvh.h"
#include "scene/bvh/scene_bvh.h"
#include "scene/bvh/wide_bvh.h"
#include "test_meshes.h"

namespace {
using fh::glsl::intersect_triangle;
using fh::glsl::make_ray_precomp;
using fh::glsl::TriangleHit;
using glm::dvec3;
using glm::vec3;

constexpr float INF = std::numeric_limits<float>::infinity();

struct Hit {
    float t = INF;
    uint32_t triangle = fh::gpu::INVALID_INDEX;
    float b1 = 0.0f, b2 = 0.0f;
};

TriangleHit intersect(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, float t_max = INF) {
    return intersect_triangle(make_ray_precomp(o, d), p0, p1, p2, t_max);
}

// Triangles and their BVH in leaf order, as the GPU sees them: the wide nodes' quantised boxes.
struct Accel {
    std::vector<vec3> positions;  // leaf order, 3 per triangle
    fh::Bvh bvh;
    std::vector<fh::gpu::BvhWideNode> wide;
    vec3 scene_min{0.0f}, scene_max{0.0f};  // the bounds the padding is taken from, grown as renderer.cpp grows them
    explicit Accel(const std::vector<vec3>& p) : bvh(fh::build_bvh(p)) {
        fh::SceneBvh level = fh::make_single_level(bvh);
        wide = std::move(level.nodes);
        const vec3 grow = (level.bounds_hi - level.bounds_lo) * (1.0f / 64.0f);
        scene_min = level.bounds_lo - grow;
        scene_max = level.bounds_hi + grow;
        for (uint32_t t : level.triangle_order) positions.insert(positions.end(), {p[3 * t], p[3 * t + 1], p[3 * t + 2]});
    }
    size_t triangle_count() const { return positions.size() / 3; }
};

// Every child whose box the GPU's slab test enters (the node frame, padded for the whole scene), in slot order.
Hit trace_bvh(const Accel& a, vec3 o, vec3 d) {
    const auto pre = make_ray_precomp(o, d);
    const float pad = fh::glsl::box_padding(o, a.scene_min, a.scene_max);
    const vec3 inv_dir = fh::glsl::make_safe_inverse_dir(d, pad);
    Hit best;
    std::vector<uint32_t> stack = {0};
    while (!stack.empty()) {
        const fh::gpu::BvhWideNode& n = a.wide[stack.back()];
        stack.pop_back();
        for (uint32_t k = 0; k < fh::gpu::BVH_WIDTH; ++k) {
            const fh::WideChild c = fh::read_wide_child(n, k);
            if (c.index == fh::gpu::INVALID_INDEX) continue;
            const auto frame = fh::glsl::make_node_frame(c.node_origin, c.step, o, inv_dir, pad);
            const glm::vec2 range = fh::glsl::child_entry_exit(frame, vec3(fh::glsl::near_planes(frame, c.lo_q, c.hi_q)),
                                                               vec3(fh::glsl::far_planes(frame, c.lo_q, c.hi_q)), best.t);
            if (!(range.x <= range.y)) continue;
            if (c.count == 0) {
                stack.push_back(c.index);
                continue;
            }
            for (uint32_t t = c.index; t < c.index + c.count; ++t) {
                const TriangleHit h = intersect_triangle(pre, a.positions[3 * t], a.positions[3 * t + 1],
                                                         a.positions[3 * t + 2], best.t);
                if (h.hit != 0u) best = {h.t, t, h.b1, h.b2};
            }
        }
    }
    return best;
}

Hit trace_brute_force(const Accel& a, vec3 o, vec3 d) {
    const auto pre = make_ray_precomp(o, d);
    Hit best;
    for (uint32_t t = 0; t < a.triangle_count(); ++t) {
        const TriangleHit h = intersect_triangle(pre, a.positions[3 * t], a.positions[3 * t + 1], a.positions[3 * t + 2], best.t);
        if (h.hit != 0u) best = {h.t, t, h.b1, h.b2};
    }
    return best;
}

// Double-precision reference (Moller & Trumbore 1997, edges inclusive): closest t, and the smallest
// barycentric of that hit (how close it is to an edge).
struct ReferenceHit {
    double t = INFINITY;
    double edge_distance = 1.0;
};

ReferenceHit trace_reference(const Accel& a, vec3 o_f, vec3 d_f) {
    const dvec3 o(o_f), d(d_f);
    ReferenceHit best;
    for (size_t t = 0; t < a.triangle_count(); ++t) {
        const dvec3 p0(a.positions[3 * t]), e1 = dvec3(a.positions[3 * t + 1]) - p0, e2 = dvec3(a.positions[3 * t + 2]) - p0;
        const dvec3 q = glm::cross(d, e2);
        const double det = glm::dot(e1, q);
        if (det == 0.0) continue;
        const dvec3 s = o - p0;
        const double b1 = glm::dot(s, q) / det;
        const dvec3 r = glm::cross(s, e1);
        const double b2 = glm::dot(d, r) / det;
        const double dist = glm::dot(e2, r) / det;
        if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || dist <= 0 || dist >= best.t) continue;
        best = {dist, std::min({b1, b2, 1 - b1 - b2})};
    }
    return best;
}

// Compares BVH, float brute force and the double reference for one ray; returns true if the double
// reference disagrees only where the ray grazes an edge (ambiguous in float).
void check_ray(const Accel& a, vec3 o, vec3 d, size_t& ambiguous) {
    const Hit bvh = trace_bvh(a, o, d);
    const Hit brute = trace_brute_force(a, o, d);
    ASSERT_EQ(bvh.t, brute.t) << "BVH traversal and brute force disagree";
    const ReferenceHit ref = trace_reference(a, o, d);
    const bool ref_hit = std::isfinite(ref.t), hit = bvh.triangle != fh::gpu::INVALID_INDEX;
    const double scale = glm::length(dvec3(d));
    if (ref_hit && hit && std::abs(double(bvh.t) - ref.t) * scale <= 1e-4 * std::max(1.0, ref.t * scale)) return;
    if (!ref_hit && !hit) return;
    // Disagreement: acceptable only for a reference hit within 1e-5 of an edge, or a float hit whose
    // reference counterpart is.
    const bool near_edge = ref_hit ? ref.edge_distance < 1e-5 : std::min({bvh.b1, bvh.b2, 1 - bvh.b1 - bvh.b2}) < 1e-5f;
    ASSERT_TRUE(near_edge) << "o " << o.x << " " << o.y << " " << o.z << " d " << d.x << " " << d.y << " " << d.z
                           << " float t " << bvh.t << " double t " << ref.t;
    ++ambiguous;
}

TEST(Intersect, SingleTriangleCases) {
    const vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
    TriangleHit h = intersect({0.25f, 0.5f, 1}, {0, 0, -1}, p0, p1, p2);
    ASSERT_EQ(h.hit, 1u);
    EXPECT_EQ(h.t, 1.0f);
    EXPECT_FLOAT_EQ(h.b1, 0.25f);  // weight of p1 = x
    EXPECT_FLOAT_EQ(h.b2, 0.5f);   // weight of p2 = y
    EXPECT_EQ(intersect({0.25f, 0.5f, -2}, {0, 0, 1}, p0, p1, p2).t, 2.0f);  // back faces count
    EXPECT_EQ(intersect({0.25f, 0.5f, 1}, {0, 0, 1}, p0, p1, p2).hit, 0u);   // behind the origin
    EXPECT_EQ(intersect({0.25f, 0.5f, 1}, {0, 0, -1}, p0, p1, p2, 1.0f).hit, 0u);  // t_max is exclusive
    EXPECT_EQ(intersect({0.25f, 0.5f, 1}, {0, 0, -1}, p0, p1, p2, 1.0001f).hit, 1u);
    EXPECT_EQ(intersect({0.25f, 0.25f, 0}, {1, 0, 0}, p0, p1, p2).hit, 0u);  // in the plane
    EXPECT_EQ(intersect({0.75f, 0.75f, 1}, {0, 0, -1}, p0, p1, p2).hit, 0u); // outside
    EXPECT_EQ(intersect({0.1f, 0.1f, 1}, {0, 0, -1}, p0, p1, {2, 0, 0}).hit, 0u);  // no area
    // On the shared edge of two triangles, both report the hit; so does a shared vertex.
    EXPECT_EQ(intersect({0.5f, 0, 1}, {0, 0, -1}, p0, p1, p2).hit, 1u);
    EXPECT_EQ(intersect({0.5f, 0, 1}, {0, 0, -1}, p1, p0, {0.5f, -1, 0}).hit, 1u);
    EXPECT_EQ(intersect({0, 0, 1}, {0, 0, -1}, p0, p1, p2).hit, 1u);
}

TEST(Intersect, BarycentricsReproduceTheHitPoint) {
    fh::test::Rng rng(5);
    int hits = 0;
    for (int i = 0; i < 10000; ++i) {
        const vec3 p0 = rng.uniform3(-1, 1), p1 = rng.uniform3(-1, 1), p2 = rng.uniform3(-1, 1);
        const vec3 o = rng.uniform3(-3, 3), d = rng.uniform3(-1, 1) * 0.5f + 0.5f * (p0 - o);
        const TriangleHit h = intersect(o, d, p0, p1, p2);
        if (h.hit == 0u) continue;
        ++hits;
        const vec3 from_t = o + h.t * d, from_b = (1 - h.b1 - h.b2) * p0 + h.b1 * p1 + h.b2 * p2;
        EXPECT_LT(glm::length(from_t - from_b), 1e-4f);
        EXPECT_GE(h.b1, 0.0f);
        EXPECT_GE(h.b2, 0.0f);
        EXPECT_LE(h.b1 + h.b2, 1.0f + 1e-6f);
    }
    EXPECT_GT(hits, 500);
}

TEST(Intersect, BvhAgreesWithBruteForceOnRandomRays) {
    std::vector<vec3> p = fh::test::make_random_soup(3000, 11, 5.0f, 1.0f);
    const auto sphere = fh::test::make_sphere({0, 0, 0}, 3.0f, 24, 48).flatten();
    p.insert(p.end(), sphere.begin(), sphere.end());
    const Accel a(p);
    fh::test::Rng rng(12);
    size_t ambiguous = 0, rays = 0;
    for (int i = 0; i < 3000; ++i, ++rays) check_ray(a, rng.uniform3(-8, 8), rng.uniform3(-1, 1), ambiguous);
    // Axis-aligned and two-axis directions: exact zeros in the direction.
    const vec3 directions[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, 0.6f, -0.8f}, {0.8f, 0, 0.6f}};
    for (const vec3& d : directions)
        for (int i = 0; i < 400; ++i, ++rays) check_ray(a, rng.uniform3(-8, 8), d, ambiguous);
    EXPECT_LT(double(ambiguous), 1e-3 * double(rays)) << ambiguous << " of " << rays;
}

// Rays from `origins` aimed exactly at every target must hit something near the target.
void expect_watertight(const Accel& a, const std::vector<vec3>& targets, fh::test::Rng& rng,
                       vec3 (*make_origin)(vec3, fh::test::Rng&)) {
    size_t misses = 0;
    for (const vec3& target : targets) {
        const vec3 o = make_origin(target, rng);
        const vec3 d = target - o;
        const Hit h = trace_bvh(a, o, d);
        const Hit b = trace_brute_force(a, o, d);
        EXPECT_EQ(h.t, b.t) << std::hexfloat << h.t << " " << b.t << " tri " << h.triangle << " " << b.triangle;
        if (h.triangle == fh::gpu::INVALID_INDEX) ++misses;
        else EXPECT_NEAR(h.t, 1.0f, 1e-4f);  // the target is the first surface point on the ray
    }
    EXPECT_EQ(misses, 0u) << "rays leaked through shared vertices or edges";
}

// Interior vertices and edge midpoints of a mesh (edges shared by two triangles).
std::vector<vec3> shared_points(const fh::test::Mesh& m, bool interior_only_grid, uint32_t n) {
    std::vector<vec3> targets;
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const vec3& v = m.vertices[i];
        if (!interior_only_grid || (std::abs(v.x) < 1 - 1.0f / n && std::abs(v.y) < 1 - 1.0f / n)) targets.push_back(v);
    }
    for (size_t t = 0; t < m.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const vec3 mid = 0.5f * (m.vertices[m.indices[t + k]] + m.vertices[m.indices[t + (k + 1) % 3]]);
            if (!interior_only_grid || (std::abs(mid.x) < 0.999f && std::abs(mid.y) < 0.999f)) targets.push_back(mid);
        }
    return targets;
}

TEST(Intersect, IsWatertightOnAGrid) {
    const uint32_t n = 32;
    const fh::test::Mesh grid = fh::test::make_grid(n, 0.2f);
    const Accel a(grid.flatten());
    fh::test::Rng rng(21);
    const auto targets = shared_points(grid, true, n);
    expect_watertight(a, targets, rng, [](vec3, fh::test::Rng& r) { return r.uniform3(-2, 2) + vec3(0, 0, 4); });
    // Straight down (two zero direction components), from exactly above each target.
    expect_watertight(a, targets, rng, [](vec3 t, fh::test::Rng& r) { return t + vec3(0, 0, 1.0f + r.uniform() * 0.0f); });
    // From below, with flat shallow rays that cross many triangles' planes.
    expect_watertight(a, targets, rng, [](vec3 t, fh::test::Rng& r) { return t + vec3(r.uniform() - 0.5f, r.uniform() - 0.5f, -0.5f); });
}

TEST(Intersect, IsWatertightOnAClosedSphere) {
    const fh::test::Mesh sphere = fh::test::make_sphere({0.5f, -0.25f, 0.125f}, 2.0f, 24, 48);
    const Accel a(sphere.flatten());
    fh::test::Rng rng(22);
    const auto targets = shared_points(sphere, false, 0);
    // From inside, every ray must hit; aimed at vertices (the poles join 48 triangles) and edge midpoints.
    expect_watertight(a, targets, rng, [](vec3, fh::test::Rng& r) { return vec3(0.5f, -0.25f, 0.125f) + r.uniform3(-1, 1); });
    expect_watertight(a, targets, rng, [](vec3, fh::test::Rng&) { return vec3(0.5f, -0.25f, 0.125f); });
    // From outside, along the outward radial direction (front-facing for every triangle around the target).
    expect_watertight(a, targets, rng, [](vec3 t, fh::test::Rng&) { return t + 3.0f * (t - vec3(0.5f, -0.25f, 0.125f)); });
}

}  // namespace
