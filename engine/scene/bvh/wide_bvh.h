// The BVH as the GPU traverses it: the binary SAH tree collapsed into 4-wide nodes with quantised child boxes
// (layout.h BvhWideNode).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/layout.h"

namespace fh {

// One child slot of a wide node as traversal reads it.
struct WideChild {
    glm::vec3 node_origin{0.0f}, step{0.0f};  // the node's frame: plane q of an axis lies at node_origin + q * step
    glm::uvec3 lo_q{0u}, hi_q{0u};            // this child's planes, in steps
    glm::vec3 lo{0.0f}, hi{0.0f};             // the same planes as float sums (the exact ones are at or outside them)
    uint32_t index = gpu::INVALID_INDEX;  // wide node, first triangle or Instance; INVALID_INDEX: no child
    uint32_t count = 0;                   // 0: a wide node; gpu::WIDE_INSTANCE_COUNT: an instance; else triangles
};

struct WideBvh {
    // Root at 0; a node's interior children are consecutive nodes after it (layout.h BvhWideNode).
    std::vector<gpu::BvhWideNode> nodes;
    // Leaf position as the wide nodes name it -> leaf position of the binary BVH: a node's leaf children's
    // triangles are consecutive, so the triangles are reordered once more (compose with Bvh::triangle_order).
    std::vector<uint32_t> leaf_order;
    double sah_cost = 0.0;  // of the wide tree (wide nodes and leaves, weighted as in make_wide_nodes) / the root's area
};

// The wide nodes of a depth-first binary BVH (layout.h BvhNode), collapsed at least SAH cost (SAH_NODE_COST per wide
// node, SAH_TRIANGLE_COST per triangle; Ylitie et al. 2017): each wide node takes up to four of the nodes below a binary
// interior node, and a subtree of at most max_leaf triangles may become one leaf. A BVH that is one leaf gives one node
// with that leaf as its only child. Each quantised box contains its binary node's box. Throws std::invalid_argument
// for a leaf of more than gpu::WIDE_MAX_LEAF triangles, a binary tree not laid out depth-first, or more nodes or leaves
// than a wide node can name. Large trees are collapsed on all hardware threads unless `on_threads` is false; the
// nodes are the same either way (sah_cost is summed in another order).
WideBvh make_wide_nodes(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf, bool on_threads = true);

// Slot k's kind (layout.h BvhWideNode): 0 a wide node, 1 .. WIDE_MAX_LEAF triangles, WIDE_INSTANCE_COUNT an instance,
// WIDE_NO_CHILD none.
uint32_t read_wide_kind(const gpu::BvhWideNode& node, uint32_t k);

// The first interior child's index (without the kinds sharing its word).
uint32_t read_first_node(const gpu::BvhWideNode& node);

WideChild read_wide_child(const gpu::BvhWideNode& node, uint32_t k);

// The sign of (origin + q * step) - bound in exact arithmetic (step a power of two, q < 256): how the quantised boxes
// are rounded outwards, and how tests check that they hold their triangles.
int compare_dequantised(float origin, uint32_t q, float step, float bound);

// Moves a node's children (a mesh's tree placed after others in one array): its interior children by node_offset (a
// node without any keeps first_node as it is), its leaves by leaf_offset. Throws std::invalid_argument for a first
// child past gpu::WIDE_MAX_FIRST_NODE or gpu::WIDE_MAX_INDEX.
void offset_wide_node(gpu::BvhWideNode& node, uint32_t node_offset, uint32_t leaf_offset);

// Makes every leaf child of `node` (each one "triangle": an instance's box) an instance (top level).
void mark_instance_leaves(gpu::BvhWideNode& node);

// The most entries the traversal stack (traverse.glsl) can hold while tracing through `nodes` from the root: a visit
// pushes every hit child but the nearest, so the bound is the largest sum of (children - 1) over the nodes on one
// root-to-leaf path, through instances into their meshes' trees.
uint32_t measure_stack_bound(const std::vector<gpu::BvhWideNode>& nodes, const std::vector<gpu::Instance>& instances);

}  // namespace fh
