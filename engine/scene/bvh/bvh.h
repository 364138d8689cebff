// Bounding volume hierarchy over world-space triangles: binned SAH build, flattened for the GPU.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "shared/layout.h"

namespace fh {

// Surface area heuristic costs (Goldsmith & Salmon 1987; MacDonald & Booth 1990): visiting a node costs SAH_NODE_COST,
// testing one triangle SAH_TRIANGLE_COST; a node is reached by a random ray with probability area(node) / area(root).
// The binary build and the collapse into wide nodes (wide_bvh.h) weigh by the same two.
constexpr double SAH_NODE_COST = 1.0;
constexpr double SAH_TRIANGLE_COST = 1.0;

struct BvhOptions {
    uint32_t max_leaf_size = 4;  // 1 .. 2^BVH_LEAF_COUNT_BITS - 1; larger nodes are always split
    uint32_t bin_count = 16;     // SAH bins per axis, 2 .. 256 (Wald 2007 uses 16 or 32)
    uint32_t max_depth = 64;     // no leaf deeper than this (root: 0), the GPU's traversal stack size;
                                 // SAH splits that would break it become median splits
    // The top levels of splits whose second subtree is offered to the other hardware threads (helper_threads.h);
    // 0: one thread. The nodes are the same either way.
    uint32_t parallel_levels = 8;
};

struct Bvh {
    // Depth-first, root at 0 (layout.h): an interior node's first child is the next node, the second is at
    // child_or_first; a leaf's triangles are triangle_order[child_or_first .. + count).
    std::vector<gpu::BvhNode> nodes;
    std::vector<uint32_t> triangle_order;  // leaf order index -> original triangle index
    double sah_cost = 0.0;     // expected cost of a random ray (SAH_NODE_COST, SAH_TRIANGLE_COST) / root area
    uint32_t max_leaf_size = 0;  // the options': no leaf holds more, nor may a wide leaf (wide_bvh.h)
    uint32_t leaf_count = 0;
    uint32_t max_depth = 0;    // depth of the deepest leaf, root at depth 0 (a traversal stack needs this many)
    double build_seconds = 0.0;
};

// Triangles in a leaf (0: an interior node).
inline uint32_t leaf_count(const gpu::BvhNode& node) {
    return node.count_and_axis & ((1u << gpu::BVH_LEAF_COUNT_BITS) - 1u);
}

// Builds a BVH over `positions` (3 per triangle). Deterministic: the same input gives the same nodes.
// Throws std::invalid_argument for no triangles, non-finite positions or options out of range (including
// more than max_leaf_size * 2^max_depth triangles).
Bvh build_bvh(std::span<const glm::vec3> positions, const BvhOptions& options = {});

// The same over boxes (corners[2 i] = min, corners[2 i + 1] = max of box i): the top level of a two-level
// BVH, whose "triangles" are instances.
Bvh build_bvh_over_boxes(std::span<const glm::vec3> corners, const BvhOptions& options = {});

}  // namespace fh
