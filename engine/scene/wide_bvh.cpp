// Collapsing the binary BVH into quantised 4-wide nodes (layout.h BvhWideNode), and reading them back.
#include "scene/wide_bvh.h"

#include "scene/bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
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

// The plane q steps above origin as a float sum (the product is exact: q < 256 times a power of two). The shader
// never forms it (intersect.glsl takes each plane's distance as one fma), but the tests read boxes through it.
float dequantise(float origin, uint32_t q, float step) { return origin + float(q) * step; }

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

namespace {

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

// Up to four binary nodes: a wide node's children.
struct Children {
    uint32_t node[gpu::BVH_WIDTH];
    uint32_t size = 0;
};

// The SAH-optimal collapse (Ylitie et al. 2017, sec. 3.1, with four slots): cost[n][i - 1] is the least expected cost
// (SAH_NODE_COST per wide node, SAH_TRIANGLE_COST per triangle, each weighted by its box's area) of binary node n's
// subtree held in at most i slots of a wide node. One slot holds n as a leaf (at most max_leaf triangles) or as a wide
// node over n; i > 1 slots are shared between n's two children, or i - 1 do as well.
struct CollapsePlan {
    std::vector<std::array<float, gpu::BVH_WIDTH>> cost;
    // Per node: bit 0, one slot holds n as a leaf; for i = 2 .. 4, bits 2 (i - 2) + 1 and 2 (i - 2) + 2, the left
    // child's share k of i slots (0: i - 1 slots); bits 7 and 8, the left child's share of the four slots of the
    // wide node over n.
    std::vector<uint16_t> choice;
    std::vector<uint32_t> count, first;  // the subtree's triangles: how many, the first in leaf order
};

constexpr uint32_t NODE_SHARE_SHIFT = 7;
uint32_t share_shift(uint32_t slots) { return 2 * (slots - 2) + 1; }

CollapsePlan plan_collapse(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf) {
    CollapsePlan p;
    const size_t size = nodes.size();
    p.cost.resize(size);
    p.choice.assign(size, 0);
    p.count.resize(size);
    p.first.resize(size);
    // Children come after their parents (depth-first layout), so one pass from the back sees them first.
    for (size_t n = size; n-- > 0;) {
        const gpu::BvhNode& b = nodes[n];
        const double area = surface_area(b);
        if (const uint32_t count = leaf_count(b)) {
            p.count[n] = count;
            p.first[n] = b.child_or_first;
            p.cost[n].fill(float(area * SAH_TRIANGLE_COST * count));
            p.choice[n] = 1;
            continue;
        }
        const size_t l = n + 1, r = b.child_or_first;
        if (r <= l || r >= size || p.first[r] != p.first[l] + p.count[l])
            throw std::invalid_argument("wide_bvh.cpp: binary node " + std::to_string(n) +
                                        " is not laid out depth-first with its subtree's triangles consecutive");
        p.count[n] = p.count[l] + p.count[r];
        p.first[n] = p.first[l];
        // The cheapest share of `slots` between the two children (the left one's share in `left`).
        auto share = [&](uint32_t slots, uint32_t& left) {
            double best = INFINITY;
            for (uint32_t k = 1; k < slots; ++k) {
                const double c = double(p.cost[l][k - 1]) + double(p.cost[r][slots - k - 1]);
                if (c < best) best = c, left = k;
            }
            return best;
        };
        uint32_t node_share = 1;
        const double as_node = area * SAH_NODE_COST + share(gpu::BVH_WIDTH, node_share);
        const double as_leaf = p.count[n] <= max_leaf ? area * SAH_TRIANGLE_COST * p.count[n] : INFINITY;
        uint32_t choice = node_share << NODE_SHARE_SHIFT | (as_leaf <= as_node ? 1u : 0u);
        p.cost[n][0] = float(std::min(as_leaf, as_node));
        for (uint32_t slots = 2; slots <= gpu::BVH_WIDTH; ++slots) {
            uint32_t left = 1;
            const double shared = share(slots, left);
            const bool fewer = !(shared < double(p.cost[n][slots - 2]));
            p.cost[n][slots - 1] = fewer ? p.cost[n][slots - 2] : float(shared);
            choice |= (fewer ? 0u : left) << share_shift(slots);
        }
        p.choice[n] = uint16_t(choice);
    }
    return p;
}

bool is_planned_leaf(const CollapsePlan& p, uint32_t n) { return (p.choice[n] & 1u) != 0; }

// Appends the slots of n's subtree in at most `slots` slots, in tree order (first child first).
void gather_slots(const std::vector<gpu::BvhNode>& nodes, const CollapsePlan& p, uint32_t n, uint32_t slots,
                  Children& c) {
    for (; slots > 1 && !leaf_count(nodes[n]); --slots) {
        const uint32_t left = (p.choice[n] >> share_shift(slots)) & 3u;
        if (left == 0) continue;
        gather_slots(nodes, p, n + 1, left, c);
        gather_slots(nodes, p, nodes[n].child_or_first, slots - left, c);
        return;
    }
    c.node[c.size++] = n;
}

// The children of the wide node over binary node n (n itself for a BVH that is one leaf).
Children collect_children(const std::vector<gpu::BvhNode>& nodes, const CollapsePlan& p, uint32_t n) {
    Children c;
    if (leaf_count(nodes[n])) {
        c.node[c.size++] = n;
        return c;
    }
    const uint32_t left = (p.choice[n] >> NODE_SHARE_SHIFT) & 3u;
    gather_slots(nodes, p, n + 1, left, c);
    gather_slots(nodes, p, nodes[n].child_or_first, gpu::BVH_WIDTH - left, c);
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
        const double inverse_step = std::ldexp(1.0, 127 - int(biased));
        w.exponents |= biased << (8 * axis);
        for (uint32_t k = 0; k < children.size; ++k) {
            const gpu::BvhNode& n = nodes[children.node[k]];
            const float child_lo[3] = {n.min_x, n.min_y, n.min_z}, child_hi[3] = {n.max_x, n.max_y, n.max_z};
            *lo_words[axis] |= quantise_down(lo[axis], step, inverse_step, child_lo[axis]) << (8 * k);
            *hi_words[axis] |= quantise_up(lo[axis], step, inverse_step, child_hi[axis]) << (8 * k);
        }
    }
}

// The word holding slot k's kind (slots 0, 1: exponents; 2, 3: first_node), and where in it.
template <typename Node>
auto& kind_word(Node& node, uint32_t k) { return k < 2 ? node.exponents : node.first_node; }
uint32_t kind_shift(uint32_t k) { return gpu::WIDE_KIND_SHIFT + gpu::WIDE_COUNT_BITS * (k & 1u); }
constexpr uint32_t KIND_MASK = (1u << gpu::WIDE_COUNT_BITS) - 1u;

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
        throw std::invalid_argument("wide_bvh.cpp: BVH node " + std::to_string(first) + " is past the " +
                                    std::to_string(gpu::WIDE_MAX_FIRST_NODE) +
                                    " a wide node can name (a larger --bvh-leaf-size makes fewer nodes)");
    node.first_node = (node.first_node & ~gpu::WIDE_MAX_FIRST_NODE) | uint32_t(first);
}

void write_first_leaf(gpu::BvhWideNode& node, uint64_t first) {
    if (first > gpu::WIDE_MAX_INDEX)
        throw std::invalid_argument("wide_bvh.cpp: BVH leaf index " + std::to_string(first) + " is above the " +
                                    std::to_string(gpu::WIDE_MAX_INDEX) + " a wide node can name");
    node.first_leaf = uint32_t(first);
}

gpu::BvhWideNode make_empty_node() {
    gpu::BvhWideNode w{};
    for (uint32_t k = 0; k < gpu::BVH_WIDTH; ++k) write_wide_kind(w, k, gpu::WIDE_NO_CHILD);
    return w;
}

}  // namespace

WideBvh make_wide_nodes(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf) {
    WideBvh wide;
    if (nodes.empty()) return wide;
    const CollapsePlan plan = plan_collapse(nodes, std::min(max_leaf, gpu::WIDE_MAX_LEAF));
    // Depth-first over (binary interior node, the wide node made for it); a node's interior children are allocated
    // together, so they are consecutive, and after it.
    struct Task {
        uint32_t binary, wide;
    };
    std::vector<Task> tasks = {{0, 0}};
    wide.nodes.push_back(make_empty_node());
    double weighted_cost = 0.0;
    while (!tasks.empty()) {
        const Task task = tasks.back();
        tasks.pop_back();
        const Children children = collect_children(nodes, plan, task.binary);
        weighted_cost += SAH_NODE_COST * surface_area(nodes[task.binary]);
        gpu::BvhWideNode w = make_empty_node();
        quantise_boxes(nodes, children, w);
        const uint32_t first_node = uint32_t(wide.nodes.size());
        write_first_leaf(w, wide.leaf_order.size());
        const size_t first_task = tasks.size();
        for (uint32_t k = 0; k < children.size; ++k) {
            const uint32_t child = children.node[k];
            const uint32_t count = is_planned_leaf(plan, child) ? plan.count[child] : 0;
            if (count > gpu::WIDE_MAX_LEAF)
                throw std::invalid_argument("wide_bvh.cpp: a BVH leaf of " + std::to_string(count) +
                                            " triangles; wide nodes hold at most " + std::to_string(gpu::WIDE_MAX_LEAF));
            write_wide_kind(w, k, count);
            if (count) {
                weighted_cost += SAH_TRIANGLE_COST * count * surface_area(nodes[child]);
                for (uint32_t t = 0; t < count; ++t) wide.leaf_order.push_back(plan.first[child] + t);
            } else {
                tasks.push_back({child, uint32_t(wide.nodes.size())});
                wide.nodes.push_back(make_empty_node());
            }
        }
        std::reverse(tasks.begin() + std::ptrdiff_t(first_task), tasks.end());  // the first child's subtree next
        if (has_interior_child(w)) write_first_node(w, first_node);
        wide.nodes[task.wide] = w;
    }
    if (wide.leaf_order.size() > size_t(gpu::WIDE_MAX_INDEX) + 1)
        throw std::invalid_argument("wide_bvh.cpp: " + std::to_string(wide.leaf_order.size()) +
                                    " BVH leaf triangles; wide nodes name at most " +
                                    std::to_string(uint64_t(gpu::WIDE_MAX_INDEX) + 1));
    const double root_area = surface_area(nodes[0]);
    wide.sah_cost = root_area > 0.0 ? weighted_cost / root_area : weighted_cost;
    return wide;
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
            throw std::invalid_argument("wide_bvh.cpp: a top-level leaf of " + std::to_string(kind) +
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
