// Stability case 3, edges and vertices, where tests/gpu/test_extend_stage.cpp does not go: the same kinds of
// rays (aimed at shared vertices and edges; exactly axis-parallel; origins on BVH box planes) on meshes
// translated to 1e4 and 1e5 and scaled down to 1e-4, traced by the real extend stage on lavapipe.
// Criteria: every ray aimed at a shared vertex or edge hits, at the distance of its target; every
// axis-parallel ray finds the double-precision reference's closest hit (same triangle, or |dt| <= 1e-6 t),
// except where the reference itself sees the ray within 1e-5 (barycentric) of an edge.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "extend_harness.h"
#include "stability_geometry.h"

namespace fh::test {
namespace {

struct Placement {
    const char* name;
    glm::dvec3 centre;
    double scale;
};

const Placement PLACEMENTS[] = {
    {"translated to 1e4", {1e4, -0.5e4, 0.75e4}, 1.0},
    {"translated to 1e5", {1e5, -0.5e5, 0.75e5}, 1.0},
    {"scaled to 1e-4", {0.3e-4, -0.2e-4, 0.1e-4}, 1e-4},
};

glm::vec3 place(const Placement& at, glm::dvec3 local) { return glm::vec3(at.centre + at.scale * local); }

// Rays from `origins` (one per target) to every vertex and edge midpoint of `mesh`: the direction is computed
// in double from the float origin to the exact target and rounded once, so the ray passes the vertex or edge
// within float rounding of the direction (~1e-7 relative), whatever the translation.
void aim_at_vertices_and_edges(const Mesh& mesh, const std::function<glm::vec3(size_t)>& origin_for,
                               const std::function<bool(glm::dvec3)>& keep, std::vector<Ray>& rays,
                               std::vector<double>& distances) {
    std::vector<glm::dvec3> targets;
    for (const glm::vec3& v : mesh.vertices) targets.push_back(glm::dvec3(v));
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e)
            targets.push_back(0.5 * (glm::dvec3(mesh.vertices[mesh.indices[t + e]]) +
                                     glm::dvec3(mesh.vertices[mesh.indices[t + (e + 1) % 3]])));
    for (const glm::dvec3& target : targets) {
        if (!keep(target)) continue;
        const glm::vec3 origin = origin_for(rays.size());
        const glm::dvec3 to_target = target - glm::dvec3(origin);
        rays.push_back({origin, glm::vec3(glm::normalize(to_target))});
        distances.push_back(glm::length(to_target));
    }
}

// A closed UV sphere (poles of valence 24) seen from inside, and a bumpy grid (valence 4 and 8) seen from
// above, skipping the grid's outer boundary where a ray may pass beside the mesh.
TEST(StabilityEdgesAndVertices, RaysThroughSharedVerticesAndEdgesAllHitFarAndTiny) {
    for (const Placement& at : PLACEMENTS) {
        for (int shape = 0; shape < 2; ++shape) {
            const Mesh local = shape == 0 ? make_sphere({0.0f, 0.0f, 0.0f}, 2.0f, 12, 24) : make_grid(20, 0.05f);
            const Mesh mesh = place_mesh(local, at.centre, at.scale);
            Rng64 rng(17 + shape);
            std::vector<Ray> rays;
            std::vector<double> distances;
            auto origin_for = [&](size_t) {
                return shape == 0 ? place(at, {rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)})
                                  : place(at, {rng.uniform(-2, 2), rng.uniform(-2, 2), 3.0});
            };
            auto keep = [&](glm::dvec3 target) {
                const glm::dvec3 l = (target - at.centre) / at.scale;
                return shape == 0 || (std::abs(l.x) < 0.999 && std::abs(l.y) < 0.999);
            };
            aim_at_vertices_and_edges(mesh, origin_for, keep, rays, distances);
            const ExtendResult result = run_extend_stage(mesh.flatten(), rays);
            size_t misses = 0, wrong_distance = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                if (result.hits[i].triangle == gpu::INVALID_INDEX) {
                    ++misses;
                } else if (std::abs(double(result.hits[i].t) - distances[i]) > 1e-5 * distances[i] &&
                           ++wrong_distance <= 5) {
                    ADD_FAILURE() << at.name << ": ray " << i << " hit at t " << result.hits[i].t << ", target at "
                                  << distances[i];
                }
            }
            std::printf("[ measured ] %s, %s: %zu rays at shared vertices and edges, %zu misses (device escaped "
                        "counter %u), %zu hits away from the target\n",
                        at.name, shape == 0 ? "closed sphere" : "grid", rays.size(), misses, result.escaped_rays,
                        wrong_distance);
            EXPECT_EQ(misses, 0u) << at.name << (shape == 0 ? ", sphere" : ", grid");
            EXPECT_EQ(result.escaped_rays, uint32_t(misses));
            EXPECT_EQ(wrong_distance, 0u);
        }
    }
}

// A random soup (800 triangles in a box of half-size 10) plus a flat 16 x 16 grid (512 triangles) in the
// plane z = centre.z: exactly axis-parallel rays (two direction components exactly 0), from random origins,
// origins with one coordinate exactly on a vertex's coordinate (a BVH slab plane), and origins on grid
// inner grid vertices' x and y (rays along z through the grid's shared vertices, which must hit; rays along x
// or y in its plane, which meet it nowhere).
TEST(StabilityEdgesAndVertices, AxisParallelRaysAndOriginsOnBoxPlanesMatchDoubleReferenceFarAndTiny) {
    for (const Placement& at : PLACEMENTS) {
        std::vector<glm::vec3> positions;
        for (const glm::vec3& p : make_random_soup(800, 23)) positions.push_back(place(at, glm::dvec3(p)));
        Mesh grid = make_grid(16, 0.0f);
        for (glm::vec3& v : grid.vertices) v *= 8.0f;
        for (const glm::vec3& p : grid.flatten()) positions.push_back(place(at, glm::dvec3(p)));
        const size_t soup_vertices = 3 * 800;

        Rng64 rng(7);
        std::vector<Ray> rays;
        std::vector<bool> through_grid_vertex;  // must hit whatever the edge distance: the vertex is shared
        for (int i = 0; i < 6 * 1024; ++i) {
            glm::vec3 dir(0.0f);
            dir[i % 3] = (i / 3) % 2 ? 1.0f : -1.0f;
            glm::vec3 origin = place(at, {rng.uniform(-11, 11), rng.uniform(-11, 11), rng.uniform(-11, 11)});
            const int kind = (i / 6) % 3;
            if (kind == 1) {  // one coordinate exactly on a soup vertex's coordinate
                const size_t v = size_t(rng.uniform() * soup_vertices);
                origin[(i + 1) % 3] = positions[v][(i + 1) % 3];
            } else if (kind == 2) {  // x and y of an inner grid vertex, z on the grid plane (in-plane rays) or off it
                glm::dvec3 g;
                do {
                    const size_t v = soup_vertices + size_t(rng.uniform() * double(positions.size() - soup_vertices));
                    g = glm::dvec3(positions[v]);
                } while (std::abs((g.x - at.centre.x) / at.scale) > 7.9 || std::abs((g.y - at.centre.y) / at.scale) > 7.9);
                origin.x = float(g.x), origin.y = float(g.y);
                if (i % 3 != 2) origin.z = float(g.z);
            }
            const glm::dvec3 local = (glm::dvec3(origin) - at.centre) / at.scale;
            through_grid_vertex.push_back(kind == 2 && i % 3 == 2 && local.z * double(dir.z) < 0.0);
            rays.push_back({origin, dir});
        }
        const ExtendResult result = run_extend_stage(positions, rays);

        size_t disagreements = 0, grazing = 0, hits = 0, vertex_rays = 0, vertex_misses = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            const ReferenceHit ref = trace_reference(positions, rays[i].origin, rays[i].dir);
            const gpu::HitItem& hit = result.hits[i];
            hits += hit.triangle != gpu::INVALID_INDEX;
            if (through_grid_vertex[i]) {
                ++vertex_rays;
                vertex_misses += hit.triangle == gpu::INVALID_INDEX;
            }
            // The reference sees the ray within 1e-5 of an edge of its own closest triangle or of the one the
            // device reports: either answer is float precision, not a traversal error.
            double gpu_edge = -1.0;
            if (hit.triangle != gpu::INVALID_INDEX) {
                const glm::vec3* p = &positions[3 * hit.triangle];
                gpu_edge = signed_edge_distance(glm::dvec3(rays[i].origin), glm::dvec3(rays[i].dir), glm::dvec3(p[0]),
                                                glm::dvec3(p[1]), glm::dvec3(p[2]));
            }
            const bool near_edge = (ref.triangle != gpu::INVALID_INDEX && ref.edge_distance < 1e-5) ||
                                   (hit.triangle != gpu::INVALID_INDEX && std::abs(gpu_edge) < 1e-5);
            bool agree;
            if (ref.triangle == gpu::INVALID_INDEX) agree = hit.triangle == gpu::INVALID_INDEX;
            else if (hit.triangle == gpu::INVALID_INDEX) agree = false;
            else agree = hit.triangle == ref.triangle || std::abs(double(hit.t) - ref.t) <= 1e-6 * ref.t;
            if (!agree && near_edge && !through_grid_vertex[i]) {
                ++grazing;
            } else if (!agree && ++disagreements <= 5) {
                ADD_FAILURE() << at.name << ": ray " << i << " origin (" << rays[i].origin.x << ", " << rays[i].origin.y
                              << ", " << rays[i].origin.z << ") axis " << i % 3 << ": device triangle " << hit.triangle
                              << " t " << hit.t << ", reference " << ref.triangle << " t " << ref.t;
            }
        }
        std::printf("[ measured ] %s: %zu axis-parallel rays (%zu hit), %zu disagree with the double reference, %zu "
                    "differ only within 1e-5 of an edge; %zu rays along z through grid vertices, %zu misses\n",
                    at.name, rays.size(), hits, disagreements, grazing, vertex_rays, vertex_misses);
        EXPECT_EQ(disagreements, 0u) << at.name;
        EXPECT_EQ(vertex_misses, 0u) << at.name;
        EXPECT_GT(vertex_rays, 100u);
        EXPECT_LE(grazing, rays.size() / 1000) << at.name;
    }
}

}  // namespace
}  // namespace fh::test
