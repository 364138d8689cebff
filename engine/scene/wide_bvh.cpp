// Collapsing the binary BVH into quantised 4-wide nodes (layout.h BvhWideNode), and reading them back.
#include "scene/wide_bvh.h"

#include "scene/bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fh {
namespace {

float surface_area(const gpu::BvhNode& n) {
    const glm::vec3 d = glm::max(glm::vec3(n.max_x - n.min_x, n.max_y - n.min_y, n.max_z - n.min_z), glm::vec3(0.0f));
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

// 2^(biased - 127) for a biased exponent in 1 .. 254.
float step_of(uint32_t biased) { return std::bit_cast<float>(biased << 23); }

// What the shader computes for q steps above origin: the product is exact (q < 256 times a power of two), so the one
// rounding is the sum's, on the host as on the device.
float dequantise(float origin, uint32_t q, float step) { return origin + float(q) * step; }

// The smallest step exponent whose 255 steps reach from lo to hi as the shader sums them.
uint32_t choose_exponent(float lo, float hi) {
    const double extent = double(hi) - double(lo);
    int e = extent > 0.0 ? int(std::ceil(std::log2(extent / 255.0))) : -126;
    uint32_t biased = uint32_t(std::clamp(e, -126, 127) + 127);
    while (biased < 254 && !(dequantise(lo, 255, step_of(biased)) >= hi)) ++biased;
    return biased;
}

// Child boxes rounded outwards to whole steps: the dequantised low corner is at or below lo, the high one at or above hi.
uint32_t quantise_down(float origin, float step, float lo) {
    uint32_t q = uint32_t(std::clamp(std::floor((double(lo) - double(origin)) / double(step)), 0.0, 255.0));
    while (q > 0 && dequantise(origin, q, step) > lo) --q;
    return q;
}

uint32_t quantise_up(float origin, float step, float hi) {
    uint32_t q = uint32_t(std::clamp(std::ceil((double(hi) - double(origin)) / double(step)), 0.0, 255.0));
    while (q < 255 && dequantise(origin, q, step) < hi) ++q;
    return q;
}

// Up to four binary nodes: a wide node's children.
struct Children {
    uint32_t node[gpu::BVH_WIDTH];
    uint32_t size = 0;
};

// The binary nodes a wide node over binary node `root` gets as children: root's two, then the interior child of
// largest surface area opened into its two, until four (kept in tree order, first child first).
Children collect_children(const std::vector<gpu::BvhNode>& nodes, uint32_t root) {
    Children c;
    if (leaf_count(nodes[root])) {  // a BVH that is one leaf
        c.node[c.size++] = root;
        return c;
    }
    c.node[c.size++] = root + 1;
    c.node[c.size++] = nodes[root].child_or_first;
    while (c.size < gpu::BVH_WIDTH) {
        int open = -1;
        float open_area = 0.0f;
        for (uint32_t k = 0; k < c.size; ++k) {
            if (leaf_count(nodes[c.node[k]])) continue;
            const float area = surface_area(nodes[c.node[k]]);
            if (open < 0 || area > open_area) {
                open = int(k);
                open_area = area;
            }
        }
        if (open < 0) break;
        const uint32_t opened = c.node[open];
        for (uint32_t k = c.size; k > uint32_t(open) + 1; --k) c.node[k] = c.node[k - 1];
        c.node[open] = opened + 1;
        c.node[open + 1] = nodes[opened].child_or_first;
        ++c.size;
    }
    return c;
}

// Writes the quantised boxes of `children` (binary nodes) into `w`, in slots 0 .. children.size() - 1.
void quantise_boxes(const std::vector<gpu::BvhNode>& nodes, const Children& children, gpu::BvhWideNode& w) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t k = 0; k < children.size; ++k) {
        const gpu::BvhNode& n = nodes[children.node[k]];
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
        w.exponents |= biased << (8 * axis);
        for (uint32_t k = 0; k < children.size; ++k) {
            const gpu::BvhNode& n = nodes[children.node[k]];
            const float child_lo[3] = {n.min_x, n.min_y, n.min_z}, child_hi[3] = {n.max_x, n.max_y, n.max_z};
            *lo_words[axis] |= quantise_down(lo[axis], step, child_lo[axis]) << (8 * k);
            *hi_words[axis] |= quantise_up(lo[axis], step, child_hi[axis]) << (8 * k);
        }
    }
}

}  // namespace

std::vector<gpu::BvhWideNode> make_wide_nodes(const std::vector<gpu::BvhNode>& nodes) {
    std::vector<gpu::BvhWideNode> wide;
    if (nodes.empty()) return wide;
    auto make_empty = [] {
        gpu::BvhWideNode w{};
        w.child_0 = w.child_1 = w.child_2 = w.child_3 = gpu::INVALID_INDEX;
        return w;
    };
    // Depth-first: (binary interior node, the wide node and slot that point at it).
    struct Task {
        uint32_t binary, parent, slot;
    };
    std::vector<Task> tasks = {{0, gpu::INVALID_INDEX, 0}};
    while (!tasks.empty()) {
        const Task task = tasks.back();
        tasks.pop_back();
        const uint32_t here = uint32_t(wide.size());
        if (task.parent != gpu::INVALID_INDEX) wide_child_word(wide[task.parent], task.slot) = pack_wide_child(here, 0);
        wide.push_back(make_empty());
        const Children children = collect_children(nodes, task.binary);
        quantise_boxes(nodes, children, wide[here]);
        for (uint32_t k = children.size; k-- > 0;) {  // pushed last to first: the first child's subtree comes next
            const gpu::BvhNode& n = nodes[children.node[k]];
            const uint32_t count = leaf_count(n);
            if (count >= gpu::WIDE_INSTANCE_COUNT)
                throw std::invalid_argument("wide_bvh.cpp: a BVH leaf of " + std::to_string(count) +
                                            " triangles; wide nodes hold at most " +
                                            std::to_string(gpu::WIDE_INSTANCE_COUNT - 1));
            if (count) wide_child_word(wide[here], k) = pack_wide_child(n.child_or_first, count);
            else tasks.push_back({children.node[k], here, k});
        }
    }
    return wide;
}

uint32_t pack_wide_child(uint32_t index, uint32_t count) {
    if (index > gpu::WIDE_MAX_INDEX)
        throw std::invalid_argument("wide_bvh.cpp: BVH child index " + std::to_string(index) + " is above the " +
                                    std::to_string(gpu::WIDE_MAX_INDEX) + " a wide node can hold");
    if (count > gpu::WIDE_INSTANCE_COUNT)
        throw std::invalid_argument("wide_bvh.cpp: BVH child count " + std::to_string(count) + " is above " +
                                    std::to_string(gpu::WIDE_INSTANCE_COUNT));
    return index << gpu::WIDE_COUNT_BITS | count;
}

WideChild read_wide_child(const gpu::BvhWideNode& node, uint32_t k) {
    const uint32_t words[gpu::BVH_WIDTH] = {node.child_0, node.child_1, node.child_2, node.child_3};
    WideChild c;
    if (words[k] != gpu::INVALID_INDEX) {
        c.index = wide_word_index(words[k]);
        c.count = wide_word_count(words[k]);
    }
    const float origin[3] = {node.origin_x, node.origin_y, node.origin_z};
    const uint32_t lo[3] = {node.lo_x, node.lo_y, node.lo_z}, hi[3] = {node.hi_x, node.hi_y, node.hi_z};
    for (int axis = 0; axis < 3; ++axis) {
        const float step = step_of((node.exponents >> (8 * axis)) & 0xffu);
        c.lo[axis] = dequantise(origin[axis], (lo[axis] >> (8 * k)) & 0xffu, step);
        c.hi[axis] = dequantise(origin[axis], (hi[axis] >> (8 * k)) & 0xffu, step);
    }
    return c;
}

uint32_t measure_stack_bound(const std::vector<gpu::BvhWideNode>& nodes, const std::vector<gpu::Instance>& instances) {
    // Children (and instances' mesh roots) come after their parents, so one pass from the back sees them first.
    std::vector<uint32_t> bound(nodes.size(), 0);
    for (size_t i = nodes.size(); i-- > 0;) {
        uint32_t children = 0, below = 0;
        for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) {
            const WideChild c = read_wide_child(nodes[i], k);
            if (c.index == gpu::INVALID_INDEX) continue;
            ++children;
            if (c.count == 0) below = std::max(below, bound.at(c.index));
            else if (c.count == gpu::WIDE_INSTANCE_COUNT) below = std::max(below, bound.at(instances.at(c.index).root_node));
        }
        bound[i] = (children > 0 ? children - 1 : 0) + below;
    }
    return bound.empty() ? 0 : bound[0];
}

}  // namespace fh
