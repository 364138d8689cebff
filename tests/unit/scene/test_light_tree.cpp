// The light tree and solid-angle sampling of triangle lights: the host's build (scene/light/light_tree.h) and the very GLSL NEE runs (shaders/lib/light/light_tree.glsl
// compiled as C++). The probabilities a walk reports form a distribution over the tree's lights; the walk picks each
// light as often as that probability says (chi-square, trees of 1 to 10^4 lights, from several shading points); the
// probability the emitter hit evaluates is bit for bit the one the pick reported (what MIS needs); a light that can
// reach the point is never given probability 0, one that cannot is never picked; the depth stays within the leaf's
// path word whatever the lights.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "chi_square.h"
#include "scene/light/light_tree.h"
#include "shared/layout.h"
#include "lib/core/cpp_compat.h"

namespace fh::glsl {
using fh::gpu::FrameParams;
using fh::gpu::LightTreeNode;
using fh::gpu::LIGHT_NODE_LEAF;
using fh::gpu::LIGHT_NODE_TWO_SIDED;
using fh::gpu::LIGHT_TREE_MAX_DEPTH;
FrameParams params{};
std::vector<LightTreeNode> tree_nodes;
LightTreeNode load_light_tree_node(uint i) { return tree_nodes.at(i); }
#include "lib/sampling/sampling.glsl"
#include "lib/light/light_tree.glsl"
#include "lib/sampling/spherical_triangle.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;

// Random lights in the box [-4, 4]^3: triangles of random size, orientation and power over four decades (a tenth
// two-sided), a few point and spot lights.
std::vector<fh::LightBounds> make_lights(size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto point = [&](double r) { return glm::dvec3(r * (2 * u(rng) - 1), r * (2 * u(rng) - 1), r * (2 * u(rng) - 1)); };
    std::vector<fh::LightBounds> lights;
    for (size_t i = 0; i < count; ++i) {
        const double power = std::pow(10.0, 4.0 * u(rng));
        if (i % 17 == 5) {
            fh::gpu::PunctualLight light{};
            const glm::dvec3 p = point(4.0), d = glm::normalize(point(1.0) + glm::dvec3(0, 0, -1.5));
            light.position = glm::vec4(glm::vec3(p), 1.0f);
            light.direction = glm::vec4(glm::vec3(d), 0.0f);
            light.type = i % 34 == 5 ? fh::gpu::LIGHT_SPOT : fh::gpu::LIGHT_POINT;
            light.cos_inner = 0.9f;
            light.cos_outer = 0.7f;
            lights.push_back(fh::punctual_light_bounds(light, power));
            continue;
        }
        const glm::dvec3 c = point(4.0);
        const double size = 0.02 + 0.5 * u(rng);
        lights.push_back(fh::triangle_light_bounds(c + point(size), c + point(size), c + point(size), power, i % 10 == 3));
    }
    return lights;
}

void install(const fh::LightTree& tree, size_t lights) {
    tree_nodes = tree.nodes;
    params = FrameParams{};
    params.emitter_count = uint32_t(lights);
    params.light_tree_lights = uint32_t(lights);
}

// Shading points inside and outside the lights' box, one-sided, two-sided and without a normal.
std::vector<LightTreePoint> make_points() {
    std::vector<LightTreePoint> points;
    const vec3 positions[] = {vec3(0.0f, 0.0f, -6.0f), vec3(1.0f, -2.0f, 0.5f), vec3(9.0f, 3.0f, 2.0f)};
    const vec3 normals[] = {vec3(0.0f, 0.0f, 1.0f), normalize(vec3(0.3f, 1.0f, -0.2f)), normalize(vec3(-1.0f, 0.2f, 0.1f))};
    const uint kinds[] = {LIGHT_POINT_ONE_SIDED, LIGHT_POINT_TWO_SIDED, LIGHT_POINT_NO_NORMAL};
    for (int i = 0; i < 3; ++i) points.push_back(make_light_point(positions[i], normals[i], kinds[i]));
    return points;
}

uint32_t float_bits(float f) {
    uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

class LightTreeSizes : public testing::TestWithParam<size_t> {};

TEST_P(LightTreeSizes, PicksEachLightAsOftenAsItsReportedProbability) {
    const size_t count = GetParam();
    const std::vector<fh::LightBounds> lights = make_lights(count, 7u + uint32_t(count));
    const fh::LightTree tree = fh::build_light_tree(lights);
    ASSERT_EQ(tree.nodes.size(), 2 * count - 1);
    install(tree, count);
    const int samples = count > 1000 ? 2000000 : 400000;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (const LightTreePoint& q : make_points()) {
        // One cell per light, and one for walks that end where no light below can reach q (the union of a node's
        // bounds is looser than its children's: the walk may reach a node and find both children at importance 0).
        std::vector<double> expected(count + 1, 0.0), observed(count + 1, 0.0);
        double total = 0.0;
        for (size_t e = 0; e < count; ++e) {
            expected[e] = tree_light_pick_pdf(q, uint(e));
            total += expected[e];
        }
        ASSERT_LE(total, 1.0 + 1e-4) << "the probabilities of the tree's lights sum to " << total;
        expected[count] = std::max(0.0, 1.0 - total);
        int mismatches = 0;
        for (int i = 0; i < samples; ++i) {
            const LightTreeWalk walk = walk_light_tree(q, std::min(u01(rng), ONE_BELOW_ONE), 0u, false);
            if (!(walk.pdf > 0.0f)) {
                observed[count] += 1.0;
                continue;
            }
            ASSERT_LT(walk.entry, count);
            ASSERT_GE(walk.u, 0.0f);
            ASSERT_LT(walk.u, 1.0f);
            observed[walk.entry] += 1.0;
            // What an emitter hit evaluates for the same light from the same point: the same bits.
            if (i < 20000 && float_bits(walk.pdf) != float_bits(tree_light_pick_pdf(q, walk.entry))) ++mismatches;
        }
        EXPECT_EQ(mismatches, 0);
        const auto sure = std::find_if(expected.begin(), expected.end(), [](double p) { return p > 1.0 - 1e-6; });
        if (sure != expected.end()) {  // one cell certain (one light reaches q, or none): nothing for Pearson's test
            EXPECT_EQ(observed[size_t(sure - expected.begin())], samples);
            continue;
        }
        for (double& e : expected) e *= samples;
        const fh::test::ChiSquareResult r = fh::test::chi_square_test(observed, expected);
        EXPECT_TRUE(r.error.empty()) << r.error;
        EXPECT_GT(r.p_value, fh::test::corrected_significance(fh::test::UNIT_CHI_SQUARE_TESTS))
            << count << " lights: chi2 = " << r.statistic << ", dof = " << r.dof;
    }
}

INSTANTIATE_TEST_SUITE_P(Lights, LightTreeSizes, testing::Values(size_t(1), size_t(2), size_t(7), size_t(100), size_t(10000)));

// A triangle whose front faces the point reaches it and must get some probability; one whose back faces a one-sided
// point's normal from below cannot, and must get none (the walk never spends a sample on it).
TEST(LightTree, ZeroProbabilityExactlyWhereNoLightCanReach) {
    std::vector<fh::LightBounds> lights;
    // Above the point, facing down (reaches it) and facing up (its back to the point); small against their distance,
    // so that the point lies outside their bounding spheres (inside one, the bound cannot tell directions apart).
    lights.push_back(fh::triangle_light_bounds({-0.1, -0.1, 2}, {0, 0.1, 2}, {0.1, -0.1, 2}, 1.0, false));   // normal -z
    lights.push_back(fh::triangle_light_bounds({-0.1, -0.1, 3}, {0.1, -0.1, 3}, {0, 0.1, 3}, 100.0, false));  // normal +z
    // Below the point's surface (a floor at z = 0, one-sided): bright, two-sided, but behind the surface.
    lights.push_back(fh::triangle_light_bounds({-0.1, -0.1, -1}, {0.1, -0.1, -1}, {0, 0.1, -1}, 1000.0, true));
    const fh::LightTree tree = fh::build_light_tree(lights);
    install(tree, lights.size());
    const LightTreePoint q = make_light_point(vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), LIGHT_POINT_ONE_SIDED);
    EXPECT_NEAR(tree_light_pick_pdf(q, 0u), 1.0f, 1e-6f);
    EXPECT_EQ(tree_light_pick_pdf(q, 1u), 0.0f);
    EXPECT_EQ(tree_light_pick_pdf(q, 2u), 0.0f);
    // Two-sided (a surface that also transmits): the light below now counts.
    const LightTreePoint both = make_light_point(vec3(0.0f), vec3(0.0f, 0.0f, 1.0f), LIGHT_POINT_TWO_SIDED);
    EXPECT_GT(tree_light_pick_pdf(both, 2u), 0.5f);
}

// The packed point keeps its position bits and its normal to about 1e-4.
TEST(LightTree, PackedPointsKeepPositionAndNormal) {
    std::mt19937 rng(5);
    std::normal_distribution<float> n01;
    for (int i = 0; i < 10000; ++i) {
        const vec3 p(n01(rng) * 100.0f, n01(rng), n01(rng) * 1e-3f);
        const vec3 n = normalize(vec3(n01(rng), n01(rng), n01(rng)));
        const LightTreePoint q = unpack_light_point(pack_light_point(p, n, LIGHT_POINT_TWO_SIDED));
        ASSERT_EQ(float_bits(q.p.x), float_bits(p.x));
        ASSERT_EQ(float_bits(q.p.z), float_bits(p.z));
        ASSERT_GT(dot(q.n, n), 1.0f - 2e-8f * 1e4f) << i;
        ASSERT_EQ(q.kind, LIGHT_POINT_TWO_SIDED);
        // Packing again gives the same point: NEE and the emitter hit see the same normal.
        const LightTreePoint again = make_light_point(q.p, q.n, q.kind);
        ASSERT_EQ(float_bits(again.n.x), float_bits(q.n.x));
        ASSERT_EQ(float_bits(again.n.y), float_bits(q.n.y));
    }
}

// Lights all at one place (no split by position is possible) and lights in a line of doubling distances (every
// binned split peels one off): the depth stays within LIGHT_TREE_MAX_DEPTH, and every leaf's path leads to it.
TEST(LightTree, DepthStaysWithinTheLeafPathWhateverTheLights) {
    std::vector<fh::LightBounds> same, line;
    for (int i = 0; i < 5000; ++i)
        same.push_back(fh::triangle_light_bounds({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1.0 + i % 3, false));
    for (int i = 0; i < 3000; ++i) {
        const double x = std::ldexp(1.0, i % 900) * 1e-120;
        line.push_back(fh::triangle_light_bounds({x, 0, 0}, {x, 1e-130, 0}, {x, 0, 1e-130}, 1.0, false));
    }
    for (const auto* lights : {&same, &line}) {
        const fh::LightTree tree = fh::build_light_tree(*lights);
        EXPECT_LE(tree.depth, fh::gpu::LIGHT_TREE_MAX_DEPTH);
        const uint32_t first_leaf = uint32_t(lights->size()) - 1;
        for (uint32_t k = 0; k < lights->size(); ++k) {
            const fh::gpu::LightTreeNode& leaf = tree.nodes[first_leaf + k];
            ASSERT_EQ(leaf.emitter, k);
            uint32_t node = 0;
            for (uint32_t level = 0; level < leaf.child1; ++level)
                node = (leaf.child0 >> level) & 1u ? tree.nodes[node].child1 : tree.nodes[node].child0;
            ASSERT_EQ(node, first_leaf + k);
        }
    }
}

TEST(LightTree, BuildIsDeterministicAndBoundsItsLights) {
    const std::vector<fh::LightBounds> lights = make_lights(20000, 3);  // above the size built on helper threads
    const fh::LightTree a = fh::build_light_tree(lights), b = fh::build_light_tree(lights);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(fh::gpu::LightTreeNode)), 0);
    EXPECT_NEAR(a.nodes[0].power, std::accumulate(lights.begin(), lights.end(), 0.0,
                                                  [](double s, const fh::LightBounds& l) { return s + l.power; }),
                1e-3 * a.nodes[0].power);
    EXPECT_THROW(fh::build_light_tree({}), std::invalid_argument);
}

// Solid-angle sampling: the directions cover the spherical triangle uniformly. The triangle is cut into 16 (two
// midpoint subdivisions); each part must get samples in proportion to the solid angle it subtends (chi-square), from
// points where the triangle subtends little, a steradian, and most of a hemisphere.
TEST(SphericalTriangle, DirectionsAreUniformOverTheSolidAngle) {
    const vec3 p0(-1.0f, -0.7f, 2.0f), p1(1.5f, -0.5f, 2.2f), p2(0.1f, 1.2f, 1.8f);
    const vec3 points[] = {vec3(0.3f, 0.1f, -12.0f), vec3(0.0f, 0.0f, 0.5f), vec3(0.2f, 0.0f, 1.9f)};
    constexpr int N = 4;  // parts per edge
    auto corner = [&](int i, int j) {  // barycentrics (i / N, j / N) of p1, p2
        const float b1 = float(i) / N, b2 = float(j) / N;
        return (1.0f - b1 - b2) * p0 + b1 * p1 + b2 * p2;
    };
    for (const vec3& p : points) {
        const float total = spherical_triangle_solid_angle(p0, p1, p2, p);
        std::vector<double> expected(N * N, 0.0), observed(N * N, 0.0);
        for (int i = 0; i < N; ++i)
            for (int j = 0; i + j < N; ++j) {
                expected[size_t(i * N + j)] = spherical_triangle_solid_angle(corner(i, j), corner(i + 1, j), corner(i, j + 1), p);
            }
        // Upside-down parts get cells of their own after the upright ones.
        std::vector<double> upside(N * N, 0.0), upside_observed(N * N, 0.0);
        for (int i = 0; i < N; ++i)
            for (int j = 0; i + j + 1 < N; ++j)
                upside[size_t(i * N + j)] = spherical_triangle_solid_angle(corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1), p);
        const int samples = 400000;
        std::mt19937 rng(21);
        std::uniform_real_distribution<float> u01(0.0f, 1.0f);
        int invalid = 0;
        for (int k = 0; k < samples; ++k) {
            const SphericalTriangleSample st = sample_spherical_triangle(p0, p1, p2, p, vec2(u01(rng), u01(rng)));
            if (!st.valid) {
                ++invalid;
                continue;
            }
            const float x = st.b.x * N, y = st.b.y * N;
            const int i = std::min(int(x), N - 1), j = std::min(int(y), N - 1);
            if (i + j + 1 < N && (x - float(i)) + (y - float(j)) > 1.0f) upside_observed[size_t(i * N + j)] += 1.0;
            else observed[size_t(i * N + std::min(j, N - 1 - i))] += 1.0;
        }
        EXPECT_EQ(invalid, 0);
        double parts = 0.0;
        for (double e : expected) parts += e;
        for (double e : upside) parts += e;
        EXPECT_NEAR(parts, total, 1e-3 * total) << "the parts' solid angles add up to the whole";
        std::vector<double> all_expected, all_observed;
        for (size_t c = 0; c < expected.size(); ++c)
            if (expected[c] > 0.0) all_expected.push_back(expected[c] / total * samples), all_observed.push_back(observed[c]);
        for (size_t c = 0; c < upside.size(); ++c)
            if (upside[c] > 0.0) all_expected.push_back(upside[c] / total * samples), all_observed.push_back(upside_observed[c]);
        ASSERT_EQ(all_expected.size(), size_t(N * N));
        const fh::test::ChiSquareResult r = fh::test::chi_square_test(all_observed, all_expected);
        EXPECT_TRUE(r.error.empty()) << r.error;
        EXPECT_GT(r.p_value, fh::test::corrected_significance(fh::test::UNIT_CHI_SQUARE_TESTS))
            << "solid angle " << total << ": chi2 = " << r.statistic << ", dof = " << r.dof;
    }
}

}  // namespace
