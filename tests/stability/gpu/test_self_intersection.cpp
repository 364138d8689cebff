// Stability case 4a, self-intersection: rays spawned from random points of random triangles at every scale
// from 1e-8 to 1e8 must never hit the triangle they leave, when traced by the real extend stage on lavapipe.
//
// The spawn is computed on the CPU by the shade stage's own code, shaders/lib/geometry/surface.glsl (load_surface:
// p = b0 p0 + b1 p1 + b2 p2, its error bound, the geometric normal cross(p1 - p0, p2 - p0)) and
// shaders/lib/geometry/ray_offset.glsl (offset_ray_origin), compiled as C++ through cpp_compat.h with
// -ffp-contract=off. The GPU may fuse the interpolation into FMAs (shade.comp does not mark it `precise`);
// that changes p by a few ulps, all inside the same error bound, so the CPU spawn stands for any of them.
//
// All triangles share one scene (one BVH, one dispatch); a re-hit is a hit reported on the spawning
// triangle itself. Naive spawns (origin = p; p + 1e-4 along the normal) are traced too, to show what goes
// wrong without the error-bound offset (README table), and an origin offset to the wrong side must re-hit
// (the count can fail).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "extend_harness.h"
#include "lib/core/cpp_compat.h"
#include "stability_geometry.h"

namespace fh::glsl {
using gpu::TRIANGLE_HAS_NORMALS;
using gpu::TRIANGLE_LIGHT_SHIFT;
using gpu::TrianglePositions;
using gpu::TriangleShading;
using gpu::Instance;
// The buffer loads of bindings.glsl, from the test's triangles (flat shading: no vertex normals).
static const std::vector<glm::vec3>* g_triangles = nullptr;
static TrianglePositions load_triangle_positions(uint triangle) {
    const std::vector<glm::vec3>& p = *g_triangles;
    TrianglePositions tp{};
    tp.p0_x = p[3 * triangle].x, tp.p0_y = p[3 * triangle].y, tp.p0_z = p[3 * triangle].z;
    tp.p1_x = p[3 * triangle + 1].x, tp.p1_y = p[3 * triangle + 1].y, tp.p1_z = p[3 * triangle + 1].z;
    tp.p2_x = p[3 * triangle + 2].x, tp.p2_y = p[3 * triangle + 2].y, tp.p2_z = p[3 * triangle + 2].z;
    tp.source_index = triangle;
    return tp;
}
static TriangleShading load_triangle_shading(uint) { return TriangleShading{}; }
#include "lib/geometry/surface.glsl"
}  // namespace fh::glsl

namespace fh::test {
namespace {

constexpr size_t TRIANGLE_COUNT = 1024;
constexpr float FIXED_EPSILON = 1e-4f;   // the classic scene-unit epsilon (ray_offset.glsl's unsafe branch)

// Random triangles: each centre coordinate has a random sign and a magnitude log-uniform in [1e-8, 1e8];
// a random orientation; a size log-uniform in [1e-5, 0.3] of the largest centre coordinate; one in four
// long and thin (aspect ratio log-uniform in [1e-4, 1e-1]). Computed in double, rounded to float;
// triangles that round to zero area are drawn again.
std::vector<glm::vec3> make_triangles_at_all_scales(size_t count, uint64_t seed) {
    Rng64 rng(seed);
    std::vector<glm::vec3> p;
    while (p.size() < 3 * count) {
        glm::dvec3 c;
        for (int k = 0; k < 3; ++k) c[k] = (rng.uniform() < 0.5 ? -1.0 : 1.0) * std::pow(10.0, rng.uniform(-8, 8));
        const double size = std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)}) * std::pow(10.0, rng.uniform(-5, -0.5));
        const glm::dvec3 u = rng.unit_vector(), v = glm::normalize(glm::cross(u, rng.unit_vector()));
        glm::dvec2 q[3];
        if (p.size() / 3 % 4 == 3) {
            const double aspect = std::pow(10.0, rng.uniform(-4, -1));
            q[0] = {-0.5, 0.0}, q[1] = {0.5, 0.0}, q[2] = {rng.uniform(-0.5, 0.5), aspect};
        } else {
            for (glm::dvec2& x : q) x = glm::dvec2(rng.in_ball(1.0));
        }
        glm::vec3 t[3];
        for (int k = 0; k < 3; ++k) t[k] = glm::vec3(c + size * (q[k].x * u + q[k].y * v));
        const glm::vec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
        if (!(glm::length(n) > 0.0f) || !std::isfinite(glm::length(n))) continue;
        p.insert(p.end(), {t[0], t[1], t[2]});
    }
    return p;
}

// How the origin of a spawned ray is placed.
enum class Spawn { error_offset, opposite_side, at_hit_point, fixed_epsilon };

struct SpawnedRay {
    Ray ray;
    uint32_t triangle;
    float max_coordinate;  // largest |coordinate| of the hit point: the scale the ray lives at
};

// Direction families: uniform on the sphere (either side), grazing (angle to the triangle's plane
// log-uniform in [min_grazing, 1e-3] rad, either side), or in the plane as float rounding leaves it.
enum class Directions { uniform_and_grazing, steep, in_plane };

struct SpawnOptions {
    Spawn spawn = Spawn::error_offset;
    Directions directions = Directions::uniform_and_grazing;
    double min_grazing = 1e-6;
    bool interior_points = false;  // barycentrics at least 0.01 from every edge (else 1 in 16 on an edge/vertex)
};

// Hit points and spawned rays, computed with the shade stage's own load_surface and offset_ray_origin.
std::vector<SpawnedRay> spawn_rays(const std::vector<glm::vec3>& triangles, size_t count, uint64_t seed,
                                   const SpawnOptions& options) {
    Rng64 rng(seed);
    glsl::g_triangles = &triangles;
    std::vector<SpawnedRay> rays(count);
    const uint32_t triangle_count = uint32_t(triangles.size() / 3);
    for (size_t i = 0; i < count; ++i) {
        const uint32_t tri = uint32_t(i % triangle_count);
        // Barycentrics as the extend stage returns them: floats; sometimes exactly on an edge or a vertex.
        float b1 = float(rng.uniform()), b2 = float(rng.uniform());
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        if (options.interior_points) {
            b1 = 0.01f + 0.97f * b1, b2 = 0.01f + 0.97f * b2;  // b0 = 1 - b1 - b2 >= 0.01 as well
        } else if (i % 16 == 5) {
            const int pattern = int(i / 16 % 6);
            if (pattern == 0) b1 = 0.0f;
            if (pattern == 1) b2 = 0.0f;
            if (pattern == 2) b2 = 1.0f - b1;
            if (pattern >= 3) b1 = pattern == 4 ? 1.0f : 0.0f, b2 = pattern == 5 ? 1.0f : 0.0f;
        }
        const glsl::SurfaceHit s = glsl::load_surface(tri, b1, b2);

        // A unit vector in the plane of s.ng (double), then tilted off it.
        const glm::dvec3 ng(s.ng);
        const glm::dvec3 r = rng.unit_vector();
        const glm::dvec3 in_plane = glm::normalize(r - glm::dot(r, ng) * ng / glm::dot(ng, ng));
        const double side = rng.uniform() < 0.5 ? -1.0 : 1.0;
        glm::vec3 w;
        if (options.directions == Directions::in_plane) {
            w = glm::vec3(in_plane);
        } else if (options.directions == Directions::uniform_and_grazing && i % 4 == 3) {
            const double angle = std::exp(rng.uniform(std::log(options.min_grazing), std::log(1e-3)));
            w = glm::vec3(std::cos(angle) * in_plane + side * std::sin(angle) * glm::normalize(ng));
        } else if (options.directions == Directions::steep) {
            const double angle = rng.uniform(0.1, 1.5707963267948966);
            w = glm::vec3(std::cos(angle) * in_plane + side * std::sin(angle) * glm::normalize(ng));
        } else {
            w = glm::vec3(rng.unit_vector());
        }

        glm::vec3 origin;
        switch (options.spawn) {
            case Spawn::error_offset: origin = glsl::offset_ray_origin(s.p, s.p_error, s.ng, w); break;
            case Spawn::opposite_side: origin = glsl::offset_ray_origin(s.p, s.p_error, s.ng, -w); break;
            case Spawn::at_hit_point: origin = s.p; break;
            case Spawn::fixed_epsilon:
                origin = s.p + (glm::dot(w, s.ng) < 0.0f ? -FIXED_EPSILON : FIXED_EPSILON) * s.ng;
                break;
        }
        const glm::vec3 a = glm::abs(s.p);
        // As the shade stage does, the error-bound spawns name the triangle they leave (traverse.glsl rejects
        // a hit on it whose t is within its own rounding error); the others do not: the naive spawns because
        // no renderer that spawns that way has the rule, the wrong-side spawns because they test the triangle
        // test's sign alone.
        const bool names_origin = options.spawn == Spawn::error_offset;
        rays[i] = {{origin, w, names_origin ? tri : fh::gpu::INVALID_INDEX}, tri, std::max({a.x, a.y, a.z})};
    }
    return rays;
}

struct ReHits {
    size_t rays = 0, re_hits = 0, other_hits = 0;
    size_t band_rays[4] = {}, band_re_hits[4] = {};  // by scale: < 1e-4, < 1, < 1e4, >= 1e4
    double seconds = 0.0;
    std::vector<size_t> re_hit_rays;
    std::vector<float> re_hit_t;
};

int scale_band(float max_coordinate) {
    return max_coordinate < 1e-4f ? 0 : max_coordinate < 1.0f ? 1 : max_coordinate < 1e4f ? 2 : 3;
}

ReHits trace_spawned(const std::vector<glm::vec3>& triangles, const std::vector<SpawnedRay>& spawned) {
    std::vector<Ray> rays;
    rays.reserve(spawned.size());
    for (const SpawnedRay& s : spawned) rays.push_back(s.ray);
    const auto start = std::chrono::steady_clock::now();
    const ExtendResult result = run_extend_stage(triangles, rays);
    ReHits count;
    count.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    count.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        const uint32_t hit = result.hits[i].triangle;
        const int band = scale_band(spawned[i].max_coordinate);
        ++count.band_rays[band];
        if (hit == spawned[i].triangle) {
            ++count.re_hits, ++count.band_re_hits[band];
            count.re_hit_rays.push_back(i);
            count.re_hit_t.push_back(result.hits[i].t);
        } else if (hit != gpu::INVALID_INDEX) {
            ++count.other_hits;
        }
    }
    return count;
}

void print_re_hits(const char* name, const ReHits& c) {
    std::printf("[ measured ] %s: %zu of %zu rays re-hit their own triangle (%.3g); by scale |p| < 1e-4: %zu/%zu, "
                "< 1: %zu/%zu, < 1e4: %zu/%zu, >= 1e4: %zu/%zu; other triangles hit: %zu; %.2f s\n",
                name, c.re_hits, c.rays, double(c.re_hits) / double(c.rays), c.band_re_hits[0], c.band_rays[0],
                c.band_re_hits[1], c.band_rays[1], c.band_re_hits[2], c.band_rays[2], c.band_re_hits[3],
                c.band_rays[3], c.other_hits, c.seconds);
}

void print_first_re_hits(const std::vector<glm::vec3>& triangles, const std::vector<SpawnedRay>& spawned,
                         const ReHits& c, size_t limit) {
    for (size_t k = 0; k < std::min(limit, c.re_hit_rays.size()); ++k) {
        const SpawnedRay& s = spawned[c.re_hit_rays[k]];
        const glm::vec3 *p = &triangles[3 * s.triangle], n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
        std::printf("  re-hit: ray %zu triangle %u (%a %a %a | %a %a %a | %a %a %a) origin (%a %a %a) dir (%a %a %a) "
                    "cos to normal %.3g, t %a\n",
                    c.re_hit_rays[k], s.triangle, p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y,
                    p[2].z, s.ray.origin.x, s.ray.origin.y, s.ray.origin.z, s.ray.dir.x, s.ray.dir.y, s.ray.dir.z,
                    double(glm::dot(n, s.ray.dir)), c.re_hit_t[k]);
    }
}

// The criterion: one million spawns, directions uniform on the sphere and (one in four) grazing, 1e-6 to 1e-3
// rad off the plane: no ray may hit its own triangle. The first re-hits are printed in hex floats.
TEST(StabilitySelfIntersection, ErrorBoundOffsetNeverReHits) {
    const std::vector<glm::vec3> triangles = make_triangles_at_all_scales(TRIANGLE_COUNT, 41);
    const std::vector<SpawnedRay> spawned = spawn_rays(triangles, 1000000, 42, {});
    const ReHits c = trace_spawned(triangles, spawned);
    print_re_hits("self-intersection, error-bound offset (shade stage)", c);
    print_first_re_hits(triangles, spawned, c, 20);
    EXPECT_EQ(c.re_hits, 0u) << "re-hits of rays whose origin is on the right side of the exact plane come from the "
                                "triangle test's float t (no conservative t > error-bound check, pbrt-v4 sec. 6.8.7)";
}

// The count can fail: an origin offset to the wrong side (behind the surface for the direction taken) starts
// the ray behind the triangle, so a steep ray (0.1 .. pi/2 rad off the plane) from an interior point comes
// back through it. Only rays that the double-precision reference sees crossing the triangle clearly inside
// (1e-3 from every edge in barycentrics) count: on small or thin triangles the offset (scaled by |p|) can
// carry the crossing point outside. Expected: nearly all re-hit. The few that do not start within a few ulps
// of |p| of the plane, where the float t of the watertight test can come out with the wrong sign (the same
// error that makes ErrorBoundOffsetNeverReHits fail on large triangles).
TEST(StabilitySelfIntersection, OriginOnTheWrongSideReHits) {
    const std::vector<glm::vec3> triangles = make_triangles_at_all_scales(TRIANGLE_COUNT, 41);
    SpawnOptions options{.spawn = Spawn::opposite_side, .directions = Directions::steep, .interior_points = true};
    const std::vector<SpawnedRay> spawned = spawn_rays(triangles, 100000, 43, options);
    const ReHits c = trace_spawned(triangles, spawned);
    print_re_hits("self-intersection, origin offset to the wrong side (must re-hit)", c);
    std::vector<bool> re_hit(spawned.size(), false);
    for (size_t i : c.re_hit_rays) re_hit[i] = true;
    size_t crossing = 0, crossing_re_hits = 0;
    for (size_t i = 0; i < spawned.size(); ++i) {
        const glm::vec3* p = &triangles[3 * spawned[i].triangle];
        const ReferenceHit ref = intersect_reference(glm::dvec3(spawned[i].ray.origin), glm::dvec3(spawned[i].ray.dir),
                                                     glm::dvec3(p[0]), glm::dvec3(p[1]), glm::dvec3(p[2]));
        if (ref.t == std::numeric_limits<double>::infinity() || ref.edge_distance < 1e-3) continue;
        ++crossing;
        crossing_re_hits += re_hit[i];
    }
    std::printf("[ measured ] of which %zu cross their triangle clearly inside (double reference): %zu re-hit, "
                "%zu do not\n", crossing, crossing_re_hits, crossing - crossing_re_hits);
    EXPECT_GT(crossing, spawned.size() / 2);
    EXPECT_GE(double(crossing_re_hits), 0.99 * double(crossing));
}

// Directions in the triangle's plane, up to the rounding of the float direction (dot(w, ng) a few ulps
// either way). The shade stage never spawns them on purpose (it requires dot(wi, ng) > 0), but a sampled
// direction can be that close.
TEST(StabilitySelfIntersection, DirectionsInThePlane) {
    const std::vector<glm::vec3> triangles = make_triangles_at_all_scales(TRIANGLE_COUNT, 41);
    SpawnOptions options{.directions = Directions::in_plane};
    const std::vector<SpawnedRay> spawned = spawn_rays(triangles, 100000, 44, options);
    const ReHits c = trace_spawned(triangles, spawned);
    print_re_hits("self-intersection, error-bound offset, directions in the plane", c);
    print_first_re_hits(triangles, spawned, c, 5);
    EXPECT_EQ(c.re_hits, 0u);  // the ray runs beside the plane, at least the error bound away from it
}

// What goes wrong without care: the same spawns with the origin at the interpolated hit point, and with the
// classic fixed epsilon of 1e-4 scene units along the normal (useless where the float spacing is larger:
// ulp(1e8) = 8).
TEST(StabilitySelfIntersection, NaiveSpawnsReHit) {
    const std::vector<glm::vec3> triangles = make_triangles_at_all_scales(TRIANGLE_COUNT, 41);
    const std::vector<SpawnedRay> at_p = spawn_rays(triangles, 100000, 45, {.spawn = Spawn::at_hit_point});
    const ReHits p = trace_spawned(triangles, at_p);
    print_re_hits("self-intersection, origin = p (no offset)", p);
    const std::vector<SpawnedRay> eps = spawn_rays(triangles, 100000, 45, {.spawn = Spawn::fixed_epsilon});
    const ReHits e = trace_spawned(triangles, eps);
    print_re_hits("self-intersection, origin = p + 1e-4 ng", e);
    const std::vector<SpawnedRay> safe = spawn_rays(triangles, 100000, 45, {});
    const ReHits s = trace_spawned(triangles, safe);
    print_re_hits("self-intersection, error-bound offset (same rays)", s);
    EXPECT_GT(p.re_hits, 0u);
    EXPECT_GT(e.band_re_hits[3], 0u) << "a 1e-4 epsilon must fail for |p| >= 1e4";
}

}  // namespace
}  // namespace fh::test
