// One quantised 4-wide node (layout.h BvhWideNode): its child boxes rounded outwards to whole steps, its slots' kinds
// and indices, written by the collapse (wide_bvh.cpp) and read back by the tests and the stack bound.
#include "scene/bvh/wide_node.h"

#include "scene/bvh/wide_bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fh {
namespace {

// 2^(biased - 127) for a biased exponent in 1 .. 254.
float step_of(uint32_t biased) { return std::bit_cast<float>(biased << 23); }

// The plane q steps above origin as a float sum (the product is exact: q < 256 times a power of two). The shader
// never forms it (intersect.glsl takes each plane's distance as one fma), but the tests read boxes through it.
float dequantise(float origin, uint32_t q, float step) { return origin + float(q) * step; }

// The smallest step exponent whose 255 steps reach from lo to hi exactly.
uint32_t choose_exponent(float lo, float hi) {
    const double extent = double(hi) - double(lo);
    int e = extent > 0.0 ? int(std::ceil(std::log2(extent / 255.0))) : -126;
    uint32_t biased = uint32_t(std::clamp(e, -126, 127) + 127);
    while (biased < 254 && compare_dequantised(lo, 255, step_of(biased), hi) < 0) ++biased;
    return biased;
}

// Child boxes rounded outwards to whole steps, in exact arithmetic (what intersect.glsl's padding assumes): the low
// plane origin + q * step at or below lo, the high one at or above hi. Their float sums then are too.
// inverse_step = 1 / step, exactly (step is a power of two): multiplying by it is dividing by step, and faster.
uint32_t quantise_down(float origin, float step, double inverse_step, float lo) {
    uint32_t q = uint32_t(std::clamp(std::floor((double(lo) - double(origin)) * inverse_step), 0.0, 255.0));
    while (q > 0 && compare_dequantised(origin, q, step, lo) > 0) --q;
    return q;
}

uint32_t quantise_up(float origin, float step, double inverse_step, float hi) {
    uint32_t q = uint32_t(std::clamp(std::ceil((double(hi) - double(origin)) * inverse_step), 0.0, 255.0));
    while (q < 255 && compare_dequantised(origin, q, step, hi) < 0) ++q;
    return q;
}

// The word holding slot k's kind (slots 0, 1: exponents; 2, 3: first_node), and where in it.
template <typename Node>
auto& kind_word(Node& node, uint32_t k) { return k < 2 ? node.exponents : node.first_node; }
uint32_t kind_shift(uint32_t k) { return gpu::WIDE_KIND_SHIFT + gpu::WIDE_COUNT_BITS * (k & 1u); }
constexpr uint32_t KIND_MASK = (1u << gpu::WIDE_COUNT_BITS) - 1u;

}  // namespace

int compare_dequantised(float origin, uint32_t q, float step, float bound) {
    // The exact sum is s + e (Knuth's TwoSum in double: q * step is exact there too). s and bound are doubles, so
    // s < bound means bound >= the next double above s, which s + e (|e| at most half a spacing) cannot reach.
    const double x = origin, y = double(q) * double(step);
    const double s = x + y, y_part = s - x, e = (x - (s - y_part)) + (y - y_part);
    const double b = bound;
    if (s != b) return s < b ? -1 : 1;
    return e < 0.0 ? -1 : (e > 0.0 ? 1 : 0);
}

void quantise_boxes(const std::vector<gpu::BvhNode>& nodes, std::span<const uint32_t> children, gpu::BvhWideNode& w) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t k = 0; k < children.size(); ++k) {
        const gpu::BvhNode& n = nodes[children[k]];
        lo = glm::min(lo, glm::vec3(n.min_x, n.min_y, n.min_z));
        hi = glm::max(hi, glm::vec3(n.max_x, n.max_y, n.max_z));
    }
    w.origin_x = lo.x;
    w.origin_y = lo.y;
    w.origin_z = lo.z;
    uint32_t* lo_words[3] = {&w.lo_x, &w.lo_y, &w.lo_z};
    uint32_t* hi_words[3] = {&w.hi_x, &w.hi_y, &w.hi_z};
    for (int axis = 0; axis < 3; ++axis) {
        const uint32_t biased = choose_exponent(lo[axis], hi[axis]);
        const float step = step_of(biased);
        const double inverse_step = std::ldexp(1.0, 127 - int(biased));
        w.exponents |= biased << (8 * axis);
        for (uint32_t k = 0; k < children.size(); ++k) {
            const gpu::BvhNode& n = nodes[children[k]];
            const float child_lo[3] = {n.min_x, n.min_y, n.min_z}, child_hi[3] = {n.max_x, n.max_y, n.max_z};
            *lo_words[axis] |= quantise_down(lo[axis], step, inverse_step, child_lo[axis]) << (8 * k);
            *hi_words[axis] |= quantise_up(lo[axis], step, inverse_step, child_hi[axis]) << (8 * k);
        }
    }
}

void write_wide_kind(gpu::BvhWideNode& node, uint32_t k, uint32_t kind) {
    uint32_t& word = kind_word(node, k);
    word = (word & ~(KIND_MASK << kind_shift(k))) | kind << kind_shift(k);
}

// first_node names something only for a node with interior children; it is set, moved and checked only there.
bool has_interior_child(const gpu::BvhWideNode& node) {
    for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k)
        if (read_wide_kind(node, k) == 0) return true;
    return false;
}

void write_first_node(gpu::BvhWideNode& node, uint64_t first) {
    if (first > gpu::WIDE_MAX_FIRST_NODE)
        throw std::invalid_argument("wide_node.cpp: BVH node " + std::to_string(first) + " is past the " +
                                    std::to_string(gpu::WIDE_MAX_FIRST_NODE) +
                                    " a wide node can name (a larger --bvh-leaf-size makes fewer nodes)");
    node.first_node = (node.first_node & ~gpu::WIDE_MAX_FIRST_NODE) | uint32_t(first);
}

void write_first_leaf(gpu::BvhWideNode& node, uint64_t first) {
    if (first > gpu::WIDE_MAX_INDEX)
        throw std::invalid_argument("wide_node.cpp: BVH leaf index " + std::to_string(first) + " is above the " +
                                    std::to_string(gpu::WIDE_MAX_INDEX) + " a wide node can name");
    node.first_leaf = uint32_t(first);
}

gpu::BvhWideNode make_empty_node() {
    gpu::BvhWideNode w{};
    for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) write_wide_kind(w, k, gpu::WIDE_NO_CHILD);
    return w;
}

uint32_t read_wide_kind(const gpu::BvhWideNode& node, uint32_t k) {
    return (kind_word(node, k) >> kind_shift(k)) & KIND_MASK;
}

uint32_t read_first_node(const gpu::BvhWideNode& node) { return node.first_node & gpu::WIDE_MAX_FIRST_NODE; }

namespace {

// What read_wide_child says of the child's index and count, without its box.
void locate_wide_child(const gpu::BvhWideNode& node, uint32_t k, uint32_t& index, uint32_t& count) {
    // Interior children take consecutive nodes, leaves consecutive triangles (an instance one), in slot order.
    uint32_t next_node = read_first_node(node), next_leaf = node.first_leaf;
    for (uint32_t j = 0; j < k; ++j) {
        const uint32_t kind = read_wide_kind(node, j);
        if (kind == 0) ++next_node;
        else if (kind == gpu::WIDE_INSTANCE_COUNT) ++next_leaf;
        else if (kind != gpu::WIDE_NO_CHILD) next_leaf += kind;
    }
    const uint32_t kind = read_wide_kind(node, k);
    index = kind == gpu::WIDE_NO_CHILD ? gpu::INVALID_INDEX : (kind == 0 ? next_node : next_leaf);
    count = kind == gpu::WIDE_NO_CHILD ? 0 : kind;
}

}  // namespace

WideChild read_wide_child(const gpu::BvhWideNode& node, uint32_t k) {
    WideChild c;
    locate_wide_child(node, k, c.index, c.count);
    const float origin[3] = {node.origin_x, node.origin_y, node.origin_z};
    const uint32_t lo[3] = {node.lo_x, node.lo_y, node.lo_z}, hi[3] = {node.hi_x, node.hi_y, node.hi_z};
    for (int axis = 0; axis < 3; ++axis) {
        const float step = step_of((node.exponents >> (8 * axis)) & 0xffu);
        c.node_origin[axis] = origin[axis];
        c.step[axis] = step;
        c.lo_q[axis] = (lo[axis] >> (8 * k)) & 0xffu;
        c.hi_q[axis] = (hi[axis] >> (8 * k)) & 0xffu;
        c.lo[axis] = dequantise(origin[axis], c.lo_q[axis], step);
        c.hi[axis] = dequantise(origin[axis], c.hi_q[axis], step);
    }
    return c;
}

void offset_wide_node(gpu::BvhWideNode& node, uint32_t node_offset, uint32_t leaf_offset) {
    if (has_interior_child(node)) write_first_node(node, uint64_t(read_first_node(node)) + node_offset);
    write_first_leaf(node, uint64_t(node.first_leaf) + leaf_offset);
}

void mark_instance_leaves(gpu::BvhWideNode& node) {
    for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
        const uint32_t kind = read_wide_kind(node, k);
        if (kind == 0 || kind == gpu::WIDE_NO_CHILD) continue;
        if (kind != 1)
            throw std::invalid_argument("wide_node.cpp: a top-level leaf of " + std::to_string(kind) +
                                        " instances; each names one");
        write_wide_kind(node, k, gpu::WIDE_INSTANCE_COUNT);
    }
}

uint32_t measure_stack_bound(const std::vector<gpu::BvhWideNode>& nodes, const std::vector<gpu::Instance>& instances) {
    // Children (and instances' mesh roots) come after their parents, so one pass from the back sees them first.
    std::vector<uint32_t> bound(nodes.size(), 0);
    for (size_t i = nodes.size(); i-- > 0;) {
        uint32_t children = 0, below = 0;
        for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
            uint32_t index, count;
            locate_wide_child(nodes[i], k, index, count);
            if (index == gpu::INVALID_INDEX) continue;
            ++children;
            if (count == 0) below = std::max(below, bound.at(index));
            else if (count == gpu::WIDE_INSTANCE_COUNT) below = std::max(below, bound.at(instances.at(index).root_node));
        }
        bound[i] = (children > 0 ? children - 1 : 0) + below;
    }
    return bound.empty() ? 0 : bound[0];
}

}  // namespace fh
