// One quantised 4-wide node (layout.h BvhWideNode) as the collapse writes it (wide_bvh.cpp); the readers are in
// wide_bvh.h.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "shared/layout.h"

namespace fh {

// A node with no children: every slot's kind WIDE_NO_CHILD.
gpu::BvhWideNode make_empty_node();

// Writes the boxes of `children` (binary nodes) into `w`, slots 0 .. children.size() - 1: the node's frame (origin
// and a power-of-two step per axis) and each box rounded outwards to whole steps, exactly.
void quantise_boxes(const std::vector<gpu::BvhNode>& nodes, std::span<const uint32_t> children, gpu::BvhWideNode& w);

// Slot k's kind (read_wide_kind).
void write_wide_kind(gpu::BvhWideNode& node, uint32_t k, uint32_t kind);

// Whether a slot holds a wide node: first_node names something only then; it is set, moved and checked only there.
bool has_interior_child(const gpu::BvhWideNode& node);

// The first interior child's node and the first leaf triangle; throw std::invalid_argument past what a node can name.
void write_first_node(gpu::BvhWideNode& node, uint64_t first);
void write_first_leaf(gpu::BvhWideNode& node, uint64_t first);

}  // namespace fh
