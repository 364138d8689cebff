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
    glm::vec3 lo{0.0f}, hi{0.0f};  // the box the GPU tests: the float sums origin + q * step, as the shader forms them
    uint32_t index = gpu::INVALID_INDEX;  // wide node, first triangle or Instance; INVALID_INDEX: no child
    uint32_t count = 0;                   // 0: a wide node; gpu::WIDE_INSTANCE_COUNT: an instance; else triangles
};

// The wide nodes of a depth-first binary BVH (layout.h BvhNode), depth-first with the root at 0, so that every
// child comes after its parent. Each wide node takes the children of a binary interior node and opens the child of
// largest surface area until it has four (or only leaves are left). A BVH that is one leaf gives one node with that
// leaf as its only child. Leaves keep their triangle ranges; each quantised box contains its binary node's box.
// Throws std::invalid_argument for a leaf of more than 62 triangles or an index above gpu::WIDE_MAX_INDEX.
std::vector<gpu::BvhWideNode> make_wide_nodes(const std::vector<gpu::BvhNode>& nodes);

WideChild read_wide_child(const gpu::BvhWideNode& node, uint32_t k);

// A present child's word, index << gpu::WIDE_COUNT_BITS | count, taken apart.
inline uint32_t wide_word_index(uint32_t word) { return word >> gpu::WIDE_COUNT_BITS; }
inline uint32_t wide_word_count(uint32_t word) { return word & ((1u << gpu::WIDE_COUNT_BITS) - 1u); }

// Child k's word: index << gpu::WIDE_COUNT_BITS | count, or gpu::INVALID_INDEX when absent.
inline uint32_t& wide_child_word(gpu::BvhWideNode& node, uint32_t k) {
    uint32_t* words[gpu::BVH_WIDTH] = {&node.child_0, &node.child_1, &node.child_2, &node.child_3};
    return *words[k];
}

// The word of a child: index up to gpu::WIDE_MAX_INDEX, count up to gpu::WIDE_INSTANCE_COUNT. Throws
// std::invalid_argument for either out of range.
uint32_t pack_wide_child(uint32_t index, uint32_t count);

// Calls f(index, count) on every present child slot of `node` (count as in WideChild); f may rewrite both.
template <typename F>
void for_each_wide_child(gpu::BvhWideNode& node, F&& f) {
    for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
        uint32_t& word = wide_child_word(node, k);
        if (word == gpu::INVALID_INDEX) continue;
        uint32_t index = wide_word_index(word), count = wide_word_count(word);
        f(index, count);
        word = pack_wide_child(index, count);
    }
}

// The most entries the traversal stack (traverse.glsl) can hold while tracing through `nodes` from the root: a visit
// pushes every hit child but the nearest, so the bound is the largest sum of (children - 1) over the nodes on one
// root-to-leaf path, through instances into their meshes' trees.
uint32_t measure_stack_bound(const std::vector<gpu::BvhWideNode>& nodes, const std::vector<gpu::Instance>& instances);

}  // namespace fh
