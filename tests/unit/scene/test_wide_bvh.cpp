// make_wide_nodes: every quantised box holds its subtree's triangles exactly as the GPU dequantises it, every triangle
// is in one leaf, children follow their parents, the collapse is the least SAH cost an exhaustive search finds, and the
// traversal stack bound is what a walk of the tree gives.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <gtest/gtest.h>

#include "scene/bvh/bvh.h"
#include "scene/bvh/scene_bvh.h"
#include "scene/bvh/wide_bvh.h"
#include "test_meshes.h"

namespace {
using fh::gpu::BvhWideNode;

struct Box {
    glm::vec3 lo{INFINITY}, hi{-INFINITY};
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
};

struct Walk {
    std::vector<int> seen;  // per leaf-order triangle
    uint32_t nodes = 0, children = 0;
    uint32_t largest_leaf = 0;
};

// The exact box of the triangles under wide node `index`, checking every child's quantised box holds its part.
// order: the wide nodes' leaf positions -> triangle.
Box check_node(const std::vector<BvhWideNode>& wide, const std::vector<uint32_t>& order, std::span<const glm::vec3> p,
               uint32_t index, Walk& walk) {
    ++walk.nodes;
    Box all;
    std::vector<std::pair<fh::WideChild, Box>> present;
    for (uint32_t k = 0; k < fh::gpu::BVH_WIDTH; ++k) {
        const fh::WideChild c = fh::read_wide_child(wide.at(index), k);
        if (c.index == fh::gpu::INVALID_INDEX) continue;
        Box exact;
        if (c.count == 0) {
            EXPECT_GT(c.index, index) << "children come after their parent";
            exact = check_node(wide, order, p, c.index, walk);
        } else {
            walk.largest_leaf = std::max(walk.largest_leaf, c.count);
            for (uint32_t t = c.index; t < c.index + c.count; ++t) {
                ++walk.seen.at(t);
                for (int v = 0; v < 3; ++v) exact.grow(p[3 * size_t(order.at(t)) + v]);
            }
        }
        present.push_back({c, exact});
        all.grow(exact);
    }
    for (const auto& [c, exact] : present)
        for (int a = 0; a < 3; ++a) {
            EXPECT_LE(c.lo[a], exact.lo[a]) << "node " << index << " axis " << a;
            EXPECT_GE(c.hi[a], exact.hi[a]) << "node " << index << " axis " << a;
            // And in exact arithmetic, which intersect.glsl's node frame assumes.
            EXPECT_LE(fh::compare_dequantised(c.node_origin[a], c.lo_q[a], c.step[a], exact.lo[a]), 0)
                << "node " << index << " axis " << a;
            EXPECT_GE(fh::compare_dequantised(c.node_origin[a], c.hi_q[a], c.step[a], exact.hi[a]), 0)
                << "node " << index << " axis " << a;
            // Rounded outwards by at most two of the node's 255 steps, plus the sum's rounding.
            const float slack = 2.0f * (all.hi[a] - all.lo[a]) / 255.0f +
                                4.0f * std::max(std::abs(all.lo[a]), std::abs(all.hi[a])) * 1.2e-7f;
            EXPECT_LE(exact.lo[a] - c.lo[a], slack) << "node " << index << " axis " << a;
            EXPECT_LE(c.hi[a] - exact.hi[a], slack) << "node " << index << " axis " << a;
        }
    walk.children += uint32_t(present.size());
    EXPECT_GE(present.size(), 1u);
    return all;
}

std::vector<BvhWideNode> check_wide(std::span<const glm::vec3> p, const fh::BvhOptions& options = {}) {
    const fh::Bvh bvh = fh::build_bvh(p, options);
    const fh::WideBvh collapsed = fh::make_wide_nodes(bvh.nodes, bvh.max_leaf_size);
    const std::vector<BvhWideNode>& wide = collapsed.nodes;
    std::vector<uint32_t> order;  // what make_single_level gives
    for (uint32_t leaf : collapsed.leaf_order) order.push_back(bvh.triangle_order.at(leaf));
    EXPECT_EQ(order.size(), p.size() / 3);
    Walk walk;
    walk.seen.assign(p.size() / 3, 0);
    check_node(wide, order, p, 0, walk);
    EXPECT_EQ(walk.nodes, wide.size()) << "every node is reached once";
    EXPECT_EQ(std::count(walk.seen.begin(), walk.seen.end(), 1), std::ptrdiff_t(p.size() / 3))
        << "every triangle in exactly one leaf";
    EXPECT_LE(walk.largest_leaf, options.max_leaf_size) << "leaves merge only up to the leaf size asked for";
    // Each wide node replaces one to three binary interior nodes.
    const size_t interior = (bvh.nodes.size() - 1) / 2;
    EXPECT_LE(wide.size(), std::max<size_t>(interior, 1));
    std::printf("%zu triangles: %zu binary interior nodes, %zu wide nodes, %.2f children per wide node\n", p.size() / 3,
                interior, wide.size(), double(walk.children) / double(walk.nodes));
    return wide;
}

TEST(WideBvh, RandomSoupBoxesHoldTheirTriangles) {
    check_wide(fh::test::make_random_soup(20000, 3));
}

TEST(WideBvh, FarFromTheOriginAndTinyBoxesStayConservative) {
    // A 1e-3 soup at (148376, 1234, -223423): the quantisation step is below the coordinates' float spacing, so the
    // host's rounding of origin + q * step decides the boxes.
    auto p = fh::test::make_random_soup(3000, 5, 1e-2f, 1e-3f);
    for (glm::vec3& v : p) v += glm::vec3(148376.0f, 1234.0f, -223423.0f);
    check_wide(p);
    // Flat boxes (a grid in a plane) and huge coordinates.
    const auto grid = fh::test::make_grid(40);
    check_wide(grid.flatten());
    auto huge = fh::test::make_random_soup(2000, 7, 1e18f, 1e17f);
    check_wide(huge);
}

// The least SAH cost of a collapse, by exhaustive search rather than make_wide_nodes' table: a binary node in one slot
// is a leaf (at most max_leaf triangles) or a wide node whose children are any set of at most four nodes below it
// that opening interior nodes one at a time reaches.
struct ExhaustiveCollapse {
    const std::vector<fh::gpu::BvhNode>& nodes;
    uint32_t max_leaf;

    static double area(const fh::gpu::BvhNode& n) {  // as wide_bvh.cpp weighs a box
        const glm::vec3 d = glm::max(glm::vec3(n.max_x - n.min_x, n.max_y - n.min_y, n.max_z - n.min_z), glm::vec3(0.0f));
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
    uint32_t count(uint32_t n) const {
        const uint32_t c = fh::leaf_count(nodes[n]);
        return c ? c : count(n + 1) + count(nodes[n].child_or_first);
    }
    double as_node(uint32_t n) const {
        return area(nodes[n]) * fh::SAH_NODE_COST + fill({n + 1, nodes[n].child_or_first});
    }
    double slot(uint32_t n) const {
        const uint32_t c = count(n);
        double best = c <= max_leaf ? area(nodes[n]) * fh::SAH_TRIANGLE_COST * c : INFINITY;
        if (!fh::leaf_count(nodes[n])) best = std::min(best, as_node(n));
        return best;
    }
    double fill(const std::vector<uint32_t>& frontier) const {
        double best = 0.0;
        for (uint32_t n : frontier) best += slot(n);
        if (frontier.size() == fh::gpu::BVH_WIDTH) return best;
        for (size_t i = 0; i < frontier.size(); ++i) {
            const uint32_t n = frontier[i];
            if (fh::leaf_count(nodes[n])) continue;
            std::vector<uint32_t> opened = frontier;
            opened[i] = n + 1;
            opened.insert(opened.begin() + std::ptrdiff_t(i) + 1, nodes[n].child_or_first);
            best = std::min(best, fill(opened));
        }
        return best;
    }
};

// The top levels of a large tree are planned and made on helper threads, each subtree at ranges the plan's counts
// give: the same nodes and leaf order as one thread makes.
TEST(WideBvh, ThreadsMakeTheSameNodes) {
    for (const uint32_t triangles : {3000u, 40000u, 150000u}) {
        const auto p = fh::test::make_random_soup(triangles, 5 + triangles, 10.0f, 0.05f);
        const fh::Bvh bvh = fh::build_bvh(p);
        const fh::WideBvh one = fh::make_wide_nodes(bvh.nodes, 4, false), threads = fh::make_wide_nodes(bvh.nodes, 4);
        ASSERT_EQ(one.nodes.size(), threads.nodes.size()) << triangles;
        EXPECT_EQ(std::memcmp(one.nodes.data(), threads.nodes.data(), one.nodes.size() * sizeof(BvhWideNode)), 0)
            << triangles;
        EXPECT_EQ(one.leaf_order, threads.leaf_order) << triangles;
        EXPECT_NEAR(one.sah_cost, threads.sah_cost, 1e-9 * one.sah_cost) << triangles;
    }
}

TEST(WideBvh, CollapseIsTheLeastSahCost) {
    // Small soups (the search is exponential), leaves of one to four triangles; leaves of one merged into wide leaves of
    // up to four or thirteen.
    struct Sizes {
        uint32_t build, collapse;
    };
    int checked = 0, merged = 0;
    for (const Sizes leaf : {Sizes{1, 1}, Sizes{2, 2}, Sizes{4, 4}, Sizes{1, 4}, Sizes{1, 13}})
        for (uint32_t seed = 1; seed <= 6; ++seed) {
            const size_t triangles = 6 + 5 * seed;
            const auto p = fh::test::make_random_soup(triangles, seed * 7 + leaf.build, 10.0f, 0.5f + float(seed));
            const fh::Bvh bvh = fh::build_bvh(p, {leaf.build, 16, 64});
            if (fh::leaf_count(bvh.nodes[0])) continue;
            const fh::WideBvh wide = fh::make_wide_nodes(bvh.nodes, leaf.collapse);
            const ExhaustiveCollapse search{bvh.nodes, leaf.collapse};
            const double least = search.as_node(0) / ExhaustiveCollapse::area(bvh.nodes[0]);
            EXPECT_NEAR(wide.sah_cost, least, 1e-5 * least) << triangles << " triangles, leaves of " << leaf.build
                                                             << " merged up to " << leaf.collapse;
            ++checked;
            for (const BvhWideNode& n : wide.nodes)
                for (uint32_t k = 0; k < fh::gpu::BVH_WIDTH; ++k) {
                    const uint32_t kind = fh::read_wide_kind(n, k);
                    EXPECT_TRUE(kind == fh::gpu::WIDE_NO_CHILD || kind <= leaf.collapse);
                    merged += kind != fh::gpu::WIDE_NO_CHILD && kind > leaf.build ? 1 : 0;
                }
        }
    EXPECT_GE(checked, 25);
    EXPECT_GT(merged, 0) << "some subtrees are cheapest as one leaf";
}

TEST(WideBvh, OneLeafIsOneNodeWithOneChild) {
    const std::vector<glm::vec3> one = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<BvhWideNode> wide = check_wide(one);
    ASSERT_EQ(wide.size(), 1u);
    EXPECT_EQ(fh::read_wide_child(wide[0], 0).count, 1u);
    EXPECT_EQ(fh::read_wide_child(wide[0], 1).index, fh::gpu::INVALID_INDEX);
    EXPECT_EQ(fh::measure_stack_bound(wide, {}), 0u);
}

// Eight unit triangles in four far-apart pairs: with leaves of one triangle, the cheapest collapse is a root over four
// nodes of two leaves each (a node over two pairs would span two gaps).
std::vector<glm::vec3> make_four_pairs() {
    std::vector<glm::vec3> eight;
    for (int i = 0; i < 8; ++i) {
        const float x = 100.0f * float(i / 2) + 2.0f * float(i % 2);
        eight.insert(eight.end(), {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}});
    }
    return eight;
}

TEST(WideBvh, StackBoundIsTheWorstPathsPushes) {
    // Two leaves: one push. Four pairs (make_four_pairs): three pushes at the root and one below.
    const std::vector<glm::vec3> two = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
    EXPECT_EQ(fh::measure_stack_bound(check_wide(two, {1, 16, 64}), {}), 1u);
    const auto wide = check_wide(make_four_pairs(), {1, 16, 64});
    EXPECT_EQ(wide.size(), 5u);
    EXPECT_EQ(fh::measure_stack_bound(wide, {}), 4u);
    // A deep, list-like tree (RespectsMaxDepth's nested triangles) stays within the GPU's stack.
    std::vector<glm::vec3> nested;
    float s = 1.0f;
    for (int i = 0; i < 1000; ++i, s *= 0.98f) nested.insert(nested.end(), {{s, 0, 0}, {0, s, 0}, {0, 0, s}});
    const fh::SceneBvh deep = fh::make_single_level(fh::build_bvh(nested));
    std::printf("1000 nested triangles: binary depth %u, stack bound %u\n", deep.max_depth, deep.stack_bound);
    EXPECT_GT(deep.stack_bound, 10u);
    EXPECT_LE(deep.stack_bound, fh::gpu::TRAVERSAL_STACK_SIZE);
}

TEST(WideBvh, RefusesLeavesItCannotCount) {
    fh::gpu::BvhNode leaf{0, 0, 0, 0, 1, 1, 1, fh::gpu::WIDE_MAX_LEAF + 1u};
    EXPECT_THROW(fh::make_wide_nodes({leaf}, fh::gpu::WIDE_MAX_LEAF), std::invalid_argument);
    leaf.count_and_axis = fh::gpu::WIDE_MAX_LEAF;
    const fh::WideBvh one = fh::make_wide_nodes({leaf}, fh::gpu::WIDE_MAX_LEAF);
    ASSERT_EQ(one.nodes.size(), 1u);
    EXPECT_EQ(fh::read_wide_child(one.nodes[0], 0).count, fh::gpu::WIDE_MAX_LEAF);
    EXPECT_EQ(one.leaf_order.size(), size_t(fh::gpu::WIDE_MAX_LEAF));
}

// Indices are implicit: interior children are consecutive nodes from first_node, leaves consecutive triangles (an
// instance one) from first_leaf, in slot order; kinds share words with the exponents and first_node.
TEST(WideBvh, ReadsImplicitChildIndices) {
    // Four pairs of one-triangle leaves (make_four_pairs): a root of four nodes of two leaves each.
    const fh::WideBvh w = fh::make_wide_nodes(fh::build_bvh(make_four_pairs(), {1, 16, 64}).nodes, 1);
    ASSERT_EQ(w.nodes.size(), 5u);
    for (uint32_t k = 0; k < 4; ++k) {
        const fh::WideChild c = fh::read_wide_child(w.nodes[0], k);
        EXPECT_EQ(c.count, 0u);
        EXPECT_EQ(c.index, 1u + k) << "the root's children are nodes 1 to 4, in slot order";
        EXPECT_EQ(fh::read_wide_child(w.nodes[c.index], 0).count, 1u);
        EXPECT_EQ(fh::read_wide_child(w.nodes[c.index], 1).index, fh::read_wide_child(w.nodes[c.index], 0).index + 1u);
        EXPECT_EQ(fh::read_wide_kind(w.nodes[c.index], 2), fh::gpu::WIDE_NO_CHILD);
    }
    // A hand-made node: a node, three triangles, an instance, none.
    BvhWideNode n{};
    n.exponents = 0x7f7f7fu | (0u | 3u << 4) << fh::gpu::WIDE_KIND_SHIFT;
    n.first_node = 1234u | (fh::gpu::WIDE_INSTANCE_COUNT | fh::gpu::WIDE_NO_CHILD << 4) << fh::gpu::WIDE_KIND_SHIFT;
    n.first_leaf = 100u;
    n.hi_x = 0xffu;
    EXPECT_EQ(fh::read_wide_child(n, 0).index, 1234u);
    EXPECT_EQ(fh::read_wide_child(n, 1).index, 100u);
    EXPECT_EQ(fh::read_wide_child(n, 1).count, 3u);
    EXPECT_EQ(fh::read_wide_child(n, 2).index, 103u);
    EXPECT_EQ(fh::read_wide_child(n, 2).count, fh::gpu::WIDE_INSTANCE_COUNT);
    EXPECT_EQ(fh::read_wide_child(n, 3).index, fh::gpu::INVALID_INDEX);
    EXPECT_EQ(fh::read_wide_child(n, 0).hi.x, 255.0f) << "the kinds leave the exponents alone (step 1)";
    // Offsets (a mesh's tree placed after others) move both, keep the kinds, and refuse what the bits cannot hold.
    fh::offset_wide_node(n, 10u, 5u);
    EXPECT_EQ(fh::read_wide_child(n, 0).index, 1244u);
    EXPECT_EQ(fh::read_wide_child(n, 2).index, 108u);
    EXPECT_EQ(fh::read_wide_kind(n, 3), fh::gpu::WIDE_NO_CHILD);
    EXPECT_THROW(fh::offset_wide_node(n, fh::gpu::WIDE_MAX_FIRST_NODE, 0u), std::invalid_argument);
    EXPECT_THROW(fh::offset_wide_node(n, 0u, fh::gpu::WIDE_MAX_INDEX), std::invalid_argument);
    fh::gpu::BvhWideNode leaves_only = w.nodes[1];  // its first_node names nothing: neither moved nor checked
    fh::offset_wide_node(leaves_only, fh::gpu::WIDE_MAX_FIRST_NODE, 0u);
    EXPECT_EQ(fh::read_first_node(leaves_only), 0u);
    // The top level: a leaf of one box becomes an instance; a leaf of two is refused.
    fh::gpu::BvhWideNode top = w.nodes[1];
    fh::mark_instance_leaves(top);
    EXPECT_EQ(fh::read_wide_kind(top, 0), fh::gpu::WIDE_INSTANCE_COUNT);
    EXPECT_EQ(fh::read_wide_child(top, 1).index, fh::read_wide_child(w.nodes[1], 1).index);
    EXPECT_THROW(fh::mark_instance_leaves(n), std::invalid_argument);
}

}  // namespace
