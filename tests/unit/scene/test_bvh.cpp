// build_bvh: structural invariants of the linear BVH, determinism, degenerate input and option limits.
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <gtest/gtest.h>

#include "scene/bvh/bvh.h"
#include "test_meshes.h"

namespace {
using fh::Bvh;
using fh::BvhOptions;
using fh::gpu::BvhNode;

uint32_t leaf_size(const BvhNode& n) { return fh::leaf_count(n); }
uint32_t split_axis(const BvhNode& n) { return n.count_and_axis >> fh::gpu::BVH_LEAF_COUNT_BITS; }

bool contains(const BvhNode& outer, const BvhNode& inner) {
    return outer.min_x <= inner.min_x && outer.min_y <= inner.min_y && outer.min_z <= inner.min_z &&
           outer.max_x >= inner.max_x && outer.max_y >= inner.max_y && outer.max_z >= inner.max_z;
}

// Walks the tree from `index`, checking layout.h's invariants; returns the index after the subtree.
uint32_t check_subtree(const Bvh& bvh, std::span<const glm::vec3> p, const BvhOptions& options, uint32_t index,
                       uint32_t depth, std::vector<int>& seen, uint32_t& leaves, uint32_t& max_depth) {
    const BvhNode& node = bvh.nodes.at(index);
    if (leaf_size(node) > 0) {
        EXPECT_LE(leaf_size(node), options.max_leaf_size);
        EXPECT_EQ(split_axis(node), 0u);
        ++leaves;
        max_depth = std::max(max_depth, depth);
        BvhNode tight{1e30f, 1e30f, 1e30f, 0, -1e30f, -1e30f, -1e30f, 0};
        for (uint32_t k = 0; k < leaf_size(node); ++k) {
            const uint32_t t = bvh.triangle_order.at(node.child_or_first + k);
            ++seen.at(node.child_or_first + k);
            for (int v = 0; v < 3; ++v) {
                const glm::vec3& q = p[3 * size_t(t) + v];
                tight = {std::min(tight.min_x, q.x), std::min(tight.min_y, q.y), std::min(tight.min_z, q.z), 0,
                         std::max(tight.max_x, q.x), std::max(tight.max_y, q.y), std::max(tight.max_z, q.z), 0};
            }
        }
        // Leaf bounds are exactly the bounds of its triangles.
        EXPECT_TRUE(contains(node, tight) && contains(tight, node)) << "leaf " << index;
        return index + 1;
    }
    EXPECT_LT(split_axis(node), 3u);
    const uint32_t first = index + 1, second = node.child_or_first;
    EXPECT_TRUE(contains(node, bvh.nodes.at(first))) << "node " << index;
    EXPECT_TRUE(contains(node, bvh.nodes.at(second))) << "node " << index;
    const uint32_t after_first = check_subtree(bvh, p, options, first, depth + 1, seen, leaves, max_depth);
    EXPECT_EQ(after_first, second) << "the second child follows the first subtree (node " << index << ")";
    return check_subtree(bvh, p, options, second, depth + 1, seen, leaves, max_depth);
}

void check_bvh(const Bvh& bvh, std::span<const glm::vec3> p, const BvhOptions& options = {}) {
    const size_t n = p.size() / 3;
    ASSERT_EQ(bvh.triangle_order.size(), n);
    std::vector<uint32_t> sorted = bvh.triangle_order;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i) << "triangle_order is not a permutation";
    std::vector<int> seen(n, 0);
    uint32_t leaves = 0, max_depth = 0;
    EXPECT_EQ(check_subtree(bvh, p, options, 0, 0, seen, leaves, max_depth), bvh.nodes.size());
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(n)) << "every triangle exactly once";
    EXPECT_EQ(leaves, bvh.leaf_count);
    EXPECT_EQ(max_depth, bvh.max_depth);
    EXPECT_LE(bvh.max_depth, options.max_depth);
    EXPECT_EQ(bvh.nodes.size(), 2 * size_t(bvh.leaf_count) - 1);
    EXPECT_TRUE(std::isfinite(bvh.sah_cost));
    EXPECT_GE(bvh.build_seconds, 0.0);
}

TEST(Bvh, RandomSoupKeepsTheInvariants) {
    const auto p = fh::test::make_random_soup(20000, 1);
    for (uint32_t leaf : {1u, 4u, 8u})
        for (uint32_t bins : {16u, 32u}) {
            const BvhOptions options{leaf, bins};
            const Bvh bvh = fh::build_bvh(p, options);
            check_bvh(bvh, p, options);
            // A useful tree costs far less than testing every triangle (this soup is dense: a ray through it
            // meets ~25 triangles).
            EXPECT_LT(bvh.sah_cost, 0.02 * double(p.size() / 3));
        }
}

TEST(Bvh, SparseSoupIsCheapToTraverse) {
    const auto p = fh::test::make_random_soup(20000, 2, 10.0f, 0.02f);
    const Bvh bvh = fh::build_bvh(p);
    check_bvh(bvh, p);
    // Uniformly spread boxes: the area summed over level l grows like 2^(l/3), ~80 over 12 levels.
    EXPECT_LT(bvh.sah_cost, 100.0);
    EXPECT_GT(bvh.sah_cost, 1.0);
}

TEST(Bvh, GridAndSphereKeepTheInvariants) {
    const auto grid = fh::test::make_grid(64, 0.1f).flatten();
    check_bvh(fh::build_bvh(grid), grid);
    const auto sphere = fh::test::make_sphere({1, 2, 3}, 2.0f, 40, 80).flatten();
    check_bvh(fh::build_bvh(sphere), sphere);
}

TEST(Bvh, IsDeterministic) {
    const auto p = fh::test::make_random_soup(5000, 7);
    const Bvh a = fh::build_bvh(p), b = fh::build_bvh(p);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)), 0);
    EXPECT_EQ(a.triangle_order, b.triangle_order);
    EXPECT_EQ(a.sah_cost, b.sah_cost);
}

// The subtrees built on threads are laid out where one thread would put them: the same nodes, order and cost.
TEST(Bvh, ThreadsBuildTheSameTree) {
    const auto p = fh::test::make_random_soup(150000, 11);
    BvhOptions serial;
    serial.parallel_levels = 0;
    const Bvh a = fh::build_bvh(p, serial);
    for (uint32_t levels : {1u, 3u, 6u, BvhOptions{}.parallel_levels}) {
        BvhOptions parallel;
        parallel.parallel_levels = levels;
        const Bvh b = fh::build_bvh(p, parallel);
        check_bvh(b, p, parallel);
        ASSERT_EQ(a.nodes.size(), b.nodes.size()) << levels << " levels";
        EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)), 0) << levels;
        EXPECT_EQ(a.triangle_order, b.triangle_order) << levels;
        EXPECT_EQ(a.leaf_count, b.leaf_count);
        EXPECT_EQ(a.max_depth, b.max_depth);
        EXPECT_NEAR(a.sah_cost, b.sah_cost, 1e-9 * a.sah_cost);  // summed in another order
    }
}

TEST(Bvh, HandlesDegenerateTriangles) {
    // 1000 copies of one triangle: coincident centroids force median splits.
    std::vector<glm::vec3> same;
    for (int i = 0; i < 1000; ++i) same.insert(same.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    check_bvh(fh::build_bvh(same), same);
    // Points and segments (zero area, zero-area boxes), mixed with normal triangles.
    std::vector<glm::vec3> mixed = fh::test::make_random_soup(500, 3);
    for (int i = 0; i < 300; ++i) {
        const glm::vec3 q(float(i % 7), 0.0f, 0.0f);
        mixed.insert(mixed.end(), {q, q, q});
        mixed.insert(mixed.end(), {q, q + glm::vec3(1, 0, 0), q + glm::vec3(2, 0, 0)});
    }
    check_bvh(fh::build_bvh(mixed), mixed);
    std::vector<glm::vec3> points(3 * 100, glm::vec3(5.0f));
    const Bvh all_points = fh::build_bvh(points);
    check_bvh(all_points, points);
    // One triangle: one leaf.
    const std::vector<glm::vec3> one = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Bvh single = fh::build_bvh(one);
    ASSERT_EQ(single.nodes.size(), 1u);
    EXPECT_EQ(leaf_size(single.nodes[0]), 1u);
    EXPECT_EQ(single.nodes[0].child_or_first, 0u);
}

TEST(Bvh, RespectsMaxDepth) {
    // Geometrically shrinking nested triangles push SAH towards a deep, list-like tree.
    std::vector<glm::vec3> nested;
    float s = 1.0f;
    for (int i = 0; i < 1000; ++i, s *= 0.98f) nested.insert(nested.end(), {{s, 0, 0}, {0, s, 0}, {0, 0, s}});
    for (uint32_t depth : {8u, 10u, 64u}) {
        const BvhOptions options{4, 16, depth};
        const Bvh bvh = fh::build_bvh(nested, options);
        check_bvh(bvh, nested, options);
    }
    EXPECT_THROW(fh::build_bvh(nested, BvhOptions{4, 16, 7}), std::invalid_argument);  // 4 * 2^7 < 1000
}

TEST(Bvh, RejectsBadInput) {
    const std::vector<glm::vec3> one = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_THROW(fh::build_bvh(std::span<const glm::vec3>()), std::invalid_argument);
    EXPECT_THROW(fh::build_bvh(std::span<const glm::vec3>(one.data(), 2)), std::invalid_argument);
    EXPECT_THROW(fh::build_bvh(one, BvhOptions{0, 16}), std::invalid_argument);
    EXPECT_THROW(fh::build_bvh(one, BvhOptions{65536, 16}), std::invalid_argument);
    EXPECT_THROW(fh::build_bvh(one, BvhOptions{4, 1}), std::invalid_argument);
    std::vector<glm::vec3> nan = one;
    nan[1].y = std::nanf("");
    EXPECT_THROW(fh::build_bvh(nan), std::invalid_argument);
}

}  // namespace
