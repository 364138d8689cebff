// Collapsing the binary BVH into quantised 4-wide nodes (layout.h BvhWideNode; one node's encoding: wide_node.h).
#include "scene/bvh/wide_bvh.h"

#include "scene/bvh/bvh.h"
#include "scene/helper_threads.h"
#include "scene/bvh/wide_node.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>

namespace fh {
namespace {

float surface_area(const gpu::BvhNode& n) {
    const glm::vec3 d = glm::max(glm::vec3(n.max_x - n.min_x, n.max_y - n.min_y, n.max_z - n.min_z), glm::vec3(0.0f));
    return d.x * d.y + d.y * d.z + d.z * d.x;
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
    std::vector<uint32_t> wide_count;    // wide nodes in the subtree of the wide node over n (for an interior n)
};

constexpr uint32_t NODE_SHARE_SHIFT = 7;
uint32_t share_shift(uint32_t slots) { return 2 * (slots - 2) + 1; }

Children collect_children(const std::vector<gpu::BvhNode>& nodes, const CollapsePlan& p, uint32_t n);
bool is_planned_leaf(const CollapsePlan& p, uint32_t n);

void throw_not_depth_first(size_t n) {
    throw std::invalid_argument("wide_bvh.cpp: binary node " + std::to_string(n) +
                                " is not laid out depth-first with its subtree's triangles consecutive");
}

// Plans node n, whose children are planned; `end` is past the last node of the range being planned, which holds n's
// subtree.
// wide_count is counted only where the wide nodes are made on threads (it places their subtrees).
void plan_node(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf, size_t n, size_t end, CollapsePlan& p) {
    const gpu::BvhNode& b = nodes[n];
    const double area = surface_area(b);
    if (const uint32_t count = leaf_count(b)) {
        p.count[n] = count;
        p.first[n] = b.child_or_first;
        p.cost[n].fill(float(area * SAH_TRIANGLE_COST * count));
        p.choice[n] = 1;
        if (!p.wide_count.empty()) p.wide_count[n] = 1;  // a BVH that is one leaf: one wide node over it
        return;
    }
    const size_t l = n + 1, r = b.child_or_first;
    if (r <= l || r >= end || p.first[r] != p.first[l] + p.count[l]) throw_not_depth_first(n);
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
    if (p.wide_count.empty()) return;
    uint32_t wide_count = 1;
    const Children children = collect_children(nodes, p, uint32_t(n));
    for (uint32_t k = 0; k < children.size; ++k)
        if (!is_planned_leaf(p, children.node[k])) wide_count += p.wide_count[children.node[k]];
    p.wide_count[n] = wide_count;
}

// Binary trees and subtrees at least this large are planned, and their wide nodes made, on two threads (smaller ones
// were slower so: 20,490 triangles, 24,065 binary nodes, took 1.70 ms against 1.52 on one thread).
constexpr size_t PARALLEL_MIN_NODES = 1u << 15;
// How many levels down the planning and the wide nodes are shared out.
constexpr uint32_t PARALLEL_LEVELS = 6;

// Plans the subtree [n, end) of the depth-first layout: children come after their parents, so one pass from the back
// sees them first; the top levels plan their two subtrees on two threads.
void plan_subtree(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf, size_t n, size_t end, CollapsePlan& p,
                  uint32_t levels, HelperThreads& helpers) {
    if (levels == 0 || end - n < PARALLEL_MIN_NODES || leaf_count(nodes[n])) {
        for (size_t i = end; i-- > n;) plan_node(nodes, max_leaf, i, end, p);
        return;
    }
    const size_t r = nodes[n].child_or_first;
    if (r <= n + 1 || r >= end) throw_not_depth_first(n);
    helpers.run_both([&] { plan_subtree(nodes, max_leaf, n + 1, r, p, levels - 1, helpers); },
                     [&] { plan_subtree(nodes, max_leaf, r, end, p, levels - 1, helpers); });
    plan_node(nodes, max_leaf, n, end, p);
}

CollapsePlan plan_collapse(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf, HelperThreads& helpers,
                           bool count_wide) {
    CollapsePlan p;
    const size_t size = nodes.size();
    p.cost.resize(size);
    p.choice.assign(size, 0);
    p.count.resize(size);
    p.first.resize(size);
    if (count_wide) p.wide_count.resize(size);
    plan_subtree(nodes, max_leaf, 0, size, p, PARALLEL_LEVELS, helpers);
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

// Where wide nodes and leaf triangles go: `wide` is sized for all of them, and each subtree writes its own ranges.
struct Emitter {
    const std::vector<gpu::BvhNode>& nodes;
    const CollapsePlan& plan;
    WideBvh& wide;
};

// Makes wide node `wide_index` over binary node `binary`: its interior children take the wide nodes from next_node on
// and its leaf children's triangles the leaf positions from next_leaf on (both advanced). Returns the children's
// binary nodes, and adds the node's and its leaves' cost.
Children make_wide_node(const Emitter& e, uint32_t binary, uint32_t wide_index, uint32_t& next_node,
                        uint32_t& next_leaf, double& weighted_cost) {
    const Children children = collect_children(e.nodes, e.plan, binary);
    weighted_cost += SAH_NODE_COST * surface_area(e.nodes[binary]);
    gpu::BvhWideNode w = make_empty_node();
    quantise_boxes(e.nodes, std::span<const uint32_t>(children.node, children.size), w);
    const uint32_t first_node = next_node;
    write_first_leaf(w, next_leaf);
    for (uint32_t k = 0; k < children.size; ++k) {
        const uint32_t child = children.node[k];
        const uint32_t count = is_planned_leaf(e.plan, child) ? e.plan.count[child] : 0;
        if (count > gpu::WIDE_MAX_LEAF)
            throw std::invalid_argument("wide_bvh.cpp: a BVH leaf of " + std::to_string(count) +
                                        " triangles; wide nodes hold at most " + std::to_string(gpu::WIDE_MAX_LEAF));
        write_wide_kind(w, k, count);
        if (count) {
            weighted_cost += SAH_TRIANGLE_COST * count * surface_area(e.nodes[child]);
            for (uint32_t t = 0; t < count; ++t) e.wide.leaf_order[next_leaf++] = e.plan.first[child] + t;
        } else {
            ++next_node;
        }
    }
    if (has_interior_child(w)) write_first_node(w, first_node);
    e.wide.nodes[wide_index] = w;
    return children;
}

// The wide nodes of the subtree under wide node `wide_index` (over binary node `binary`), in the order one
// depth-first pass makes them: a node's interior children consecutive, then the first child's subtree, the second's...
// Its descendants take the wide nodes from next_node on (it returns past them), its triangles the leaf positions from
// next_leaf on. The top levels hand their children's subtrees to helper threads: the plan's counts say where each
// one's ranges begin.
double make_subtree(const Emitter& e, uint32_t binary, uint32_t wide_index, uint32_t& next_node, uint32_t next_leaf,
                    uint32_t levels, HelperThreads& helpers) {
    double weighted_cost = 0.0;
    if (levels == 0 || e.plan.wide_count.empty() || e.plan.wide_count[binary] < PARALLEL_MIN_NODES / 4) {
        struct Task {
            uint32_t binary, wide;
        };
        std::vector<Task> tasks = {{binary, wide_index}};
        while (!tasks.empty()) {
            const Task task = tasks.back();
            tasks.pop_back();
            uint32_t child_node = next_node;
            const Children children = make_wide_node(e, task.binary, task.wide, next_node, next_leaf, weighted_cost);
            const size_t first_task = tasks.size();
            for (uint32_t k = 0; k < children.size; ++k)
                if (!is_planned_leaf(e.plan, children.node[k])) tasks.push_back({children.node[k], child_node++});
            std::reverse(tasks.begin() + std::ptrdiff_t(first_task), tasks.end());  // the first child's subtree next
        }
        return weighted_cost;
    }
    uint32_t child_node = next_node;
    const Children children = make_wide_node(e, binary, wide_index, next_node, next_leaf, weighted_cost);
    struct Part {
        uint32_t binary = 0, wide = 0, next_node = 0, next_leaf = 0;
        double cost = 0.0;
    };
    std::array<Part, gpu::BVH_WIDTH> parts;
    uint32_t part_count = 0;
    for (uint32_t k = 0; k < children.size; ++k) {
        const uint32_t child = children.node[k];
        if (is_planned_leaf(e.plan, child)) continue;
        parts[part_count++] = {child, child_node++, next_node, next_leaf, 0.0};
        next_node += e.plan.wide_count[child] - 1;  // its descendants
        next_leaf += e.plan.count[child];
    }
    // Each part in a task of its own, the first on this thread; the cost adds up in slot order.
    std::array<std::function<void()>, gpu::BVH_WIDTH> tasks;
    for (uint32_t i = 0; i < part_count; ++i)
        tasks[i] = [&, i] {
            Part& part = parts[i];
            part.cost = make_subtree(e, part.binary, part.wide, part.next_node, part.next_leaf, levels - 1, helpers);
        };
    helpers.run_all(std::span<const std::function<void()>>(tasks.data(), part_count));
    for (uint32_t i = 0; i < part_count; ++i) weighted_cost += parts[i].cost;
    return weighted_cost;
}

}  // namespace

WideBvh make_wide_nodes(const std::vector<gpu::BvhNode>& nodes, uint32_t max_leaf, bool on_threads) {
    WideBvh wide;
    if (nodes.empty()) return wide;
    const uint32_t hardware = std::max(1u, std::thread::hardware_concurrency());
    const bool threads = on_threads && nodes.size() >= PARALLEL_MIN_NODES;
    HelperThreads helpers(threads ? hardware - 1 : 0);
    const CollapsePlan plan = plan_collapse(nodes, std::min(max_leaf, gpu::WIDE_MAX_LEAF), helpers, threads);
    if (plan.count[0] > size_t(gpu::WIDE_MAX_INDEX) + 1)
        throw std::invalid_argument("wide_bvh.cpp: " + std::to_string(plan.count[0]) +
                                    " BVH leaf triangles; wide nodes name at most " +
                                    std::to_string(uint64_t(gpu::WIDE_MAX_INDEX) + 1));
    // Each binary interior node, (size - 1) / 2 of them, becomes at most one wide node (a one-leaf BVH: one over the
    // leaf).
    wide.nodes.assign(threads ? plan.wide_count[0] : (nodes.size() - 1) / 2 + 1, make_empty_node());
    wide.leaf_order.resize(plan.count[0]);
    uint32_t next_node = 1;
    const double weighted_cost = make_subtree({nodes, plan, wide}, 0, 0, next_node, 0, PARALLEL_LEVELS, helpers);
    wide.nodes.resize(next_node);
    const double root_area = surface_area(nodes[0]);
    wide.sah_cost = root_area > 0.0 ? weighted_cost / root_area : weighted_cost;
    return wide;
}

}  // namespace fh
