// Binned SAH BVH build (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"),
// written straight into the depth-first linear layout the GPU traverses (pbrt-v4 LinearBVHNode).
#include "scene/bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace fh {
namespace {

// Surface area heuristic costs (Goldsmith & Salmon 1987; MacDonald & Booth 1990): visiting an interior
// node costs TRAVERSAL_COST, testing one triangle INTERSECTION_COST; a node is reached by a random ray with
// probability area(node) / area(root).
constexpr double TRAVERSAL_COST = 1.0;
constexpr double INTERSECTION_COST = 1.0;
constexpr uint32_t MAX_BINS = 256;

struct Box {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};

    void grow(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    // Half the surface area (the factor 2 cancels in every SAH ratio); 0 for an empty box.
    double half_area() const {
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return 0.0;
        const glm::dvec3 d = glm::dvec3(hi) - glm::dvec3(lo);
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

// One triangle's bounds and its original index; these are partitioned in place while building.
struct PrimRef {
    Box bounds;
    uint32_t triangle;
    glm::vec3 centroid() const { return 0.5f * (bounds.lo + bounds.hi); }
};

struct Task {
    uint32_t begin, end;   // range of PrimRefs
    uint32_t parent;       // node whose child_or_first must point here (second children), else INVALID_INDEX
    uint32_t depth;
};

struct Split {
    int axis = -1;         // -1: no split with both sides non-empty
    uint32_t last_left_bin = 0;
    double cost = std::numeric_limits<double>::infinity();  // sum of half_area * count over both sides
};

// Maps a centroid coordinate to its bin (Wald 2007 eq. 4: k1 = K (1 - eps) / extent). The same float
// arithmetic is used for binning and for partitioning, so both agree on every triangle.
struct Binner {
    glm::vec3 origin, scale;
    uint32_t count;
    uint32_t bin(const glm::vec3& c, int axis) const {
        const float f = (c[axis] - origin[axis]) * scale[axis];
        return std::min(count - 1, uint32_t(std::max(f, 0.0f)));
    }
};

struct Bin {
    Box bounds;
    uint32_t count = 0;
};
using BinScratch = std::array<std::array<Bin, MAX_BINS>, 3>;

Split find_split(const std::vector<PrimRef>& refs, const Task& task, const Box& centroids, const Binner& binner,
                 BinScratch& bins) {
    for (auto& axis_bins : bins) std::fill_n(axis_bins.begin(), binner.count, Bin{});
    for (uint32_t i = task.begin; i < task.end; ++i) {
        const glm::vec3 c = refs[i].centroid();
        for (int axis = 0; axis < 3; ++axis) {
            Bin& b = bins[axis][binner.bin(c, axis)];
            b.bounds.grow(refs[i].bounds);
            ++b.count;
        }
    }
    Split best;
    const uint32_t k = binner.count;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(centroids.hi[axis] > centroids.lo[axis])) continue;
        // Sweep from the right to get the cost of every right side, then from the left (Wald 2007 sec. 3.2).
        std::array<double, MAX_BINS> right_cost;  // [i]: cost of bins i+1 .. k-1 (-1: empty)
        Box right;
        uint32_t right_count = 0;
        for (uint32_t i = k - 1; i > 0; --i) {
            right.grow(bins[axis][i].bounds);
            right_count += bins[axis][i].count;
            right_cost[i - 1] = right_count == 0 ? -1.0 : right.half_area() * right_count;
        }
        Box left;
        uint32_t left_count = 0;
        for (uint32_t i = 0; i + 1 < k; ++i) {
            left.grow(bins[axis][i].bounds);
            left_count += bins[axis][i].count;
            if (left_count == 0 || right_cost[i] < 0.0) continue;
            const double cost = left.half_area() * left_count + right_cost[i];
            if (cost < best.cost) {
                best.axis = axis;
                best.last_left_bin = i;
                best.cost = cost;
            }
        }
    }
    return best;
}

void check_input(std::span<const glm::vec3> positions, const BvhOptions& options) {
    if (positions.empty() || positions.size() % 3 != 0)
        throw std::invalid_argument("bvh.cpp: need a positive multiple of 3 positions, got " +
                                    std::to_string(positions.size()));
    if (positions.size() / 3 >= gpu::INVALID_INDEX)
        throw std::invalid_argument("bvh.cpp: too many triangles for 32-bit indices");
    if (options.max_leaf_size < 1 || options.max_leaf_size >= (1u << gpu::BVH_LEAF_COUNT_BITS))
        throw std::invalid_argument("bvh.cpp: max_leaf_size " + std::to_string(options.max_leaf_size) +
                                    " is outside 1..65535");
    if (options.bin_count < 2 || options.bin_count > MAX_BINS)
        throw std::invalid_argument("bvh.cpp: bin_count " + std::to_string(options.bin_count) +
                                    " is outside 2..256");
    const uint32_t depth_bits = std::min(options.max_depth, 40u);
    if (options.max_depth < 1 || double(positions.size() / 3) > double(options.max_leaf_size) * std::ldexp(1.0, int(depth_bits)))
        throw std::invalid_argument("bvh.cpp: max_depth " + std::to_string(options.max_depth) +
                                    " cannot hold " + std::to_string(positions.size() / 3) + " triangles");
    for (size_t i = 0; i < positions.size(); ++i)
        if (!std::isfinite(positions[i].x) || !std::isfinite(positions[i].y) || !std::isfinite(positions[i].z))
            throw std::invalid_argument("bvh.cpp: triangle " + std::to_string(i / 3) + " has a non-finite vertex");
}

void write_bounds(gpu::BvhNode& node, const Box& b) {
    node.min_x = b.lo.x;
    node.min_y = b.lo.y;
    node.min_z = b.lo.z;
    node.max_x = b.hi.x;
    node.max_y = b.hi.y;
    node.max_z = b.hi.z;
}

Bvh build_from_refs(std::vector<PrimRef> refs, const BvhOptions& options,
                    std::chrono::steady_clock::time_point start) {
    const uint32_t triangle_count = uint32_t(refs.size());
    Bvh bvh;
    bvh.nodes.reserve(2 * size_t(triangle_count));
    double root_area = 0.0;
    double weighted_cost = 0.0;  // sum over nodes of half_area * cost of the node itself
    auto bins = std::make_unique<BinScratch>();
    std::vector<Task> stack{{0, triangle_count, gpu::INVALID_INDEX, 0}};
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        const uint32_t node_index = uint32_t(bvh.nodes.size());
        bvh.nodes.emplace_back();
        if (task.parent != gpu::INVALID_INDEX) bvh.nodes[task.parent].child_or_first = node_index;

        Box bounds, centroids;
        for (uint32_t i = task.begin; i < task.end; ++i) {
            bounds.grow(refs[i].bounds);
            centroids.grow(refs[i].centroid());
        }
        write_bounds(bvh.nodes[node_index], bounds);
        const double area = bounds.half_area();
        if (node_index == 0) root_area = area;
        const uint32_t count = task.end - task.begin;

        // Choose: leaf, SAH split, or median split (coincident centroids or a zero-area box).
        int axis = -1;
        uint32_t mid = task.begin;
        if (count > 1) {
            Split split;
            if (area > 0.0) {
                const glm::vec3 extent = centroids.hi - centroids.lo;
                Binner binner{centroids.lo, glm::vec3(0.0f), options.bin_count};
                for (int a = 0; a < 3; ++a)
                    binner.scale[a] = extent[a] > 0.0f ? float(options.bin_count) * (1.0f - 1e-6f) / extent[a] : 0.0f;
                split = find_split(refs, task, centroids, binner, *bins);
                const double leaf_cost = INTERSECTION_COST * count;
                const double split_cost = TRAVERSAL_COST + INTERSECTION_COST * split.cost / area;
                const bool prefer_leaf = split.axis < 0 || leaf_cost <= split_cost;
                if (split.axis >= 0 && !(prefer_leaf && count <= options.max_leaf_size)) {
                    axis = split.axis;
                    const uint32_t last = split.last_left_bin;
                    auto first_right = std::partition(refs.begin() + task.begin, refs.begin() + task.end,
                                                      [&](const PrimRef& r) { return binner.bin(r.centroid(), axis) <= last; });
                    mid = uint32_t(first_right - refs.begin());
                }
            }
            // Children may hold at most max_leaf_size * 2^(levels left below them) triangles, so that median
            // splits from there on still end within max_depth.
            const uint32_t levels_left = options.max_depth - std::min(options.max_depth, task.depth + 1);
            const double child_capacity = double(options.max_leaf_size) * std::ldexp(1.0, int(std::min(levels_left, 40u)));
            const bool too_deep = axis >= 0 && double(std::max(mid - task.begin, task.end - mid)) > child_capacity;
            if ((axis < 0 && count > options.max_leaf_size) || too_deep) {
                // Object median along the longest centroid axis (or box side when the centroids coincide).
                const glm::vec3 cd = centroids.hi - centroids.lo;
                const glm::vec3 d = cd == glm::vec3(0.0f) ? bounds.hi - bounds.lo : cd;
                axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
                mid = task.begin + count / 2;
                std::nth_element(refs.begin() + task.begin, refs.begin() + mid, refs.begin() + task.end,
                                 [axis](const PrimRef& l, const PrimRef& r) {
                                     const float cl = l.centroid()[axis], cr = r.centroid()[axis];
                                     return cl < cr || (cl == cr && l.triangle < r.triangle);
                                 });
            }
        }

        gpu::BvhNode& node = bvh.nodes[node_index];
        if (axis < 0) {
            node.child_or_first = task.begin;
            node.count_and_axis = count;
            weighted_cost += area * INTERSECTION_COST * count;
            ++bvh.leaf_count;
            bvh.max_depth = std::max(bvh.max_depth, task.depth);
        } else {
            node.count_and_axis = uint32_t(axis) << gpu::BVH_LEAF_COUNT_BITS;
            weighted_cost += area * TRAVERSAL_COST;
            // The first child is visited next, so it lands at node_index + 1 (depth-first layout).
            stack.push_back({mid, task.end, node_index, task.depth + 1});
            stack.push_back({task.begin, mid, gpu::INVALID_INDEX, task.depth + 1});
        }
    }

    bvh.triangle_order.resize(triangle_count);
    for (uint32_t i = 0; i < triangle_count; ++i) bvh.triangle_order[i] = refs[i].triangle;
    // A scene whose root box has no area (all triangles on one line or point) reports unnormalized cost.
    bvh.sah_cost = root_area > 0.0 ? weighted_cost / root_area : weighted_cost;
    bvh.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace

Bvh build_bvh(std::span<const glm::vec3> positions, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check_input(positions, options);
    std::vector<PrimRef> refs(positions.size() / 3);
    for (uint32_t t = 0; t < refs.size(); ++t) {
        refs[t].triangle = t;
        for (int k = 0; k < 3; ++k) refs[t].bounds.grow(positions[3 * size_t(t) + k]);
    }
    return build_from_refs(std::move(refs), options, start);
}

Bvh build_bvh_over_boxes(std::span<const glm::vec3> corners, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (corners.empty() || corners.size() % 2 != 0)
        throw std::invalid_argument("bvh.cpp: need a positive multiple of 2 box corners, got " + std::to_string(corners.size()));
    std::vector<glm::vec3> as_points(corners.begin(), corners.end());
    as_points.resize(corners.size() / 2 * 3, corners[0]);
    check_input(as_points, options);  // the limits on count and depth, and finiteness
    std::vector<PrimRef> refs(corners.size() / 2);
    for (uint32_t i = 0; i < refs.size(); ++i) {
        refs[i].triangle = i;
        refs[i].bounds.grow(corners[2 * size_t(i)]);
        refs[i].bounds.grow(corners[2 * size_t(i) + 1]);
    }
    return build_from_refs(std::move(refs), options, start);
}

}  // namespace fh
