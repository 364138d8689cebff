// The extend stage (BVH traversal + watertight triangle test, on lavapipe) against a brute-force
// double-precision reference: random rays, axis-parallel rays, origins on BVH box planes, and rays aimed
// exactly at the shared vertices and edges of meshes (which must all hit). And the connect stage's shadow rays (any
// hit up to t_max) against the same reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "../unit/scene/test_meshes.h"
#include "extend_harness.h"

namespace fh::test {
namespace {

struct ReferenceHit {
    double t = std::numeric_limits<double>::infinity();
    uint32_t triangle = gpu::INVALID_INDEX;
    double edge_distance = 1.0;  // smallest barycentric coordinate at the hit (0 = on an edge)
};

// Moller & Trumbore (1997) in double precision with inclusive edges, over every triangle.
ReferenceHit trace_reference(const std::vector<glm::vec3>& p, const Ray& ray) {
    ReferenceHit best;
    const glm::dvec3 o(ray.origin), d(ray.dir);
    for (uint32_t tri = 0; tri < p.size() / 3; ++tri) {
        const glm::dvec3 p0(p[3 * tri]), e1 = glm::dvec3(p[3 * tri + 1]) - p0, e2 = glm::dvec3(p[3 * tri + 2]) - p0;
        const glm::dvec3 q = glm::cross(d, e2);
        const double det = glm::dot(e1, q);
        if (det == 0.0) continue;
        const glm::dvec3 s = o - p0;
        const double b1 = glm::dot(s, q) / det;
        const glm::dvec3 r = glm::cross(s, e1);
        const double b2 = glm::dot(d, r) / det;
        const double t = glm::dot(e2, r) / det;
        if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0 || t >= best.t) continue;
        best = {t, tri, std::min({b1, b2, 1 - b1 - b2})};
    }
    return best;
}

// Same triangle, or the same distance within 1e-6 relative (a tie between neighbours), is agreement.
// A ray that grazes an edge (within 1e-5 in barycentrics) may also hit the neighbour or slip off the
// silhouette; that is float precision, not a traversal bug.
int count_disagreements(const std::vector<glm::vec3>& p, const std::vector<Ray>& rays, const ExtendResult& r) {
    int bad = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const ReferenceHit ref = trace_reference(p, rays[i]);
        const gpu::HitItem& hit = r.hits[i];
        const bool grazing = ref.triangle != gpu::INVALID_INDEX && ref.edge_distance < 1e-5;
        bool ok;
        if (ref.triangle == gpu::INVALID_INDEX) ok = hit.triangle == gpu::INVALID_INDEX || grazing;
        else if (hit.triangle == gpu::INVALID_INDEX) ok = grazing;
        else ok = hit.triangle == ref.triangle || std::abs(hit.t - ref.t) <= 1e-6 * ref.t || grazing;
        if (!ok && ++bad <= 5)
            ADD_FAILURE() << "ray " << i << ": gpu triangle " << hit.triangle << " t " << hit.t << ", reference "
                          << ref.triangle << " t " << ref.t;
    }
    return bad;
}

TEST(ExtendStage, RandomRaysMatchDoubleReference) {
    const std::vector<glm::vec3> soup = make_random_soup(800, 11);
    Rng rng(5);
    std::vector<Ray> rays;
    for (int i = 0; i < 8192; ++i)
        rays.push_back({rng.uniform3(-12.0f, 12.0f), glm::normalize(rng.uniform3(-1.0f, 1.0f))});
    ExtendResult result = run_extend_stage(soup, rays);
    EXPECT_EQ(count_disagreements(soup, rays, result), 0);
    int misses = 0;
    for (const auto& h : result.hits) misses += h.triangle == gpu::INVALID_INDEX;
    EXPECT_EQ(result.escaped_rays, uint32_t(misses));  // the device's escape counter counts what it reports
    EXPECT_GT(misses, 0);
    EXPECT_LT(misses, int(rays.size()));
}

// The ray sort (--sort-rays) changes only which lane traces which ray: every ray gets the same hit, to the bit, at its
// own queue index. A sort that lost or repeated a ray leaves some hits unwritten and fails here.
TEST(ExtendStage, SortedRaysGetTheSameHits) {
    const std::vector<glm::vec3> soup = make_random_soup(800, 11);
    Rng rng(7);
    std::vector<Ray> rays;
    for (int i = 0; i < 20000; ++i)  // in no order: many keys, several rays to most
        rays.push_back({rng.uniform3(-12.0f, 12.0f), glm::normalize(rng.uniform3(-1.0f, 1.0f))});
    const ExtendResult queued = run_extend_stage(soup, rays);
    const ExtendResult sorted = run_extend_stage(soup, rays, {}, true);
    ASSERT_EQ(sorted.hits.size(), queued.hits.size());
    int different = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const gpu::HitItem& a = queued.hits[i];
        const gpu::HitItem& b = sorted.hits[i];
        const bool same = a.triangle == b.triangle &&
                          (a.triangle == gpu::INVALID_INDEX || (std::memcmp(&a.t, &b.t, sizeof a.t) == 0 &&
                                                                std::memcmp(&a.b1, &b.b1, sizeof a.b1) == 0 &&
                                                                std::memcmp(&a.b2, &b.b2, sizeof a.b2) == 0));
        if (!same && ++different <= 5)
            ADD_FAILURE() << "ray " << i << ": queue order triangle " << a.triangle << " t " << a.t << ", sorted "
                          << b.triangle << " t " << b.t;
    }
    EXPECT_EQ(different, 0);
    EXPECT_EQ(sorted.escaped_rays, queued.escaped_rays);
    EXPECT_EQ(count_disagreements(soup, rays, sorted), 0);
}

TEST(ExtendStage, AxisParallelRaysAndOriginsOnBoxPlanes) {
    const std::vector<glm::vec3> soup = make_random_soup(800, 23);
    Rng rng(7);
    std::vector<Ray> rays;
    for (int i = 0; i < 6 * 1024; ++i) {
        glm::vec3 dir(0.0f);
        dir[i % 3] = (i / 3) % 2 ? 1.0f : -1.0f;  // exactly axis-parallel: two components are exactly 0
        glm::vec3 origin = rng.uniform3(-11.0f, 11.0f);
        // Every third ray starts exactly on the plane of a triangle's bounding box (a BVH slab plane).
        if (i % 3 == 0) {
            const glm::vec3& v = soup[3 * (i % (soup.size() / 3)) + (i / 7) % 3];
            origin[(i + 1) % 3] = v[(i + 1) % 3];
        }
        rays.push_back({origin, dir});
    }
    ExtendResult result = run_extend_stage(soup, rays);
    EXPECT_EQ(count_disagreements(soup, rays, result), 0);
}

// Rays aimed at every vertex and edge midpoint of a closed sphere from inside, and of a bumpy grid from
// above: a watertight traversal never lets one through.
TEST(ExtendStage, RaysThroughSharedVerticesAndEdgesAllHit) {
    for (int shape = 0; shape < 2; ++shape) {
        Mesh mesh = shape == 0 ? make_sphere({0.3f, -0.2f, 0.1f}, 2.0f, 12, 24) : make_grid(20, 0.05f);
        std::vector<glm::vec3> targets = mesh.vertices;
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            for (int e = 0; e < 3; ++e)
                targets.push_back(0.5f * (mesh.vertices[mesh.indices[t + e]] + mesh.vertices[mesh.indices[t + (e + 1) % 3]]));
        Rng rng(3 + shape);
        std::vector<Ray> rays;
        for (const glm::vec3& target : targets) {
            // Grid: skip the outer boundary, where a ray may legitimately pass beside the mesh.
            if (shape == 1 && (std::abs(target.x) >= 0.999f || std::abs(target.y) >= 0.999f)) continue;
            glm::vec3 origin = shape == 0 ? glm::vec3(0.3f, -0.2f, 0.1f) + rng.uniform3(-0.5f, 0.5f)
                                          : glm::vec3(rng.uniform3(-2.0f, 2.0f).x, rng.uniform3(-2.0f, 2.0f).y, 3.0f);
            rays.push_back({origin, glm::normalize(target - origin)});
        }
        ExtendResult result = run_extend_stage(mesh.flatten(), rays);
        int misses = 0;
        for (const auto& h : result.hits) misses += h.triangle == gpu::INVALID_INDEX;
        EXPECT_EQ(misses, 0) << (shape == 0 ? "sphere" : "grid") << ": " << misses << " of " << rays.size()
                             << " rays slipped through a shared vertex or edge";
        EXPECT_EQ(result.escaped_rays, uint32_t(misses));
    }
}

// Leaf size changes the tree, never the closest hit.
TEST(ExtendStage, LeafSizeDoesNotChangeHits) {
    const std::vector<glm::vec3> soup = make_random_soup(800, 31);
    Rng rng(9);
    std::vector<Ray> rays;
    for (int i = 0; i < 4096; ++i) rays.push_back({rng.uniform3(-12.0f, 12.0f), glm::normalize(rng.uniform3(-1, 1))});
    ExtendResult a = run_extend_stage(soup, rays, {.max_leaf_size = 1});
    ExtendResult b = run_extend_stage(soup, rays, {.max_leaf_size = 8});
    for (size_t i = 0; i < rays.size(); ++i) {
        EXPECT_EQ(a.hits[i].triangle, b.hits[i].triangle) << "ray " << i;
        if (a.hits[i].triangle == b.hits[i].triangle) {
            EXPECT_EQ(a.hits[i].t, b.hits[i].t) << "ray " << i;
        }
    }
}

// Shadow rays between two random points (as next-event estimation traces them, ending just short of the target): the
// connect stage finds a blocker exactly where the reference's closest hit lies before t_max. Rays whose closest hit
// grazes an edge or lies within 1e-5 of t_max may go either way (float precision), and are not counted.
TEST(ConnectStage, ShadowRaysAreBlockedExactlyWhereTheReferenceFindsAHitBeforeTMax) {
    const std::vector<glm::vec3> soup = make_random_soup(800, 13);
    Rng rng(17);
    std::vector<ShadowRay> rays;
    std::vector<Ray> as_rays;
    for (int i = 0; i < 8192; ++i) {
        const glm::vec3 from = rng.uniform3(-12.0f, 12.0f), to = rng.uniform3(-12.0f, 12.0f);
        const float length = glm::length(to - from);
        if (length < 1e-3f) continue;
        const glm::vec3 dir = (to - from) / length;
        rays.push_back({from, dir, length * (1.0f - 1e-4f)});
        as_rays.push_back({from, dir});
    }
    const std::vector<uint8_t> occluded = run_connect_stage(soup, rays);
    ASSERT_EQ(occluded.size(), rays.size());
    int blocked = 0, bad = 0, uncertain = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const ReferenceHit ref = trace_reference(soup, as_rays[i]);
        const bool expected = ref.t < double(rays[i].t_max);
        if (ref.edge_distance < 1e-5 || std::abs(ref.t - rays[i].t_max) <= 1e-5 * rays[i].t_max) {
            ++uncertain;
            continue;
        }
        blocked += expected;
        if ((occluded[i] != 0) != expected && ++bad <= 5)
            ADD_FAILURE() << "ray " << i << ": connect says " << (occluded[i] ? "blocked" : "clear")
                          << ", reference closest hit at t " << ref.t << " of t_max " << rays[i].t_max;
    }
    EXPECT_EQ(bad, 0);
    EXPECT_LT(uncertain, 20);
    // Both answers occur often: the test would notice a stage that blocks everything or nothing.
    EXPECT_GT(blocked, int(rays.size()) / 10);
    EXPECT_LT(blocked, int(rays.size()) * 9 / 10);
}

}  // namespace
}  // namespace fh::test
