// Binned SAH BVH build (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"),
// written straight into the depth-first linear layout the GPU traverses (pbrt-v4 LinearBVHNode).
#include "scene/bvh/bvh.h"

#include "scene/helper_threads.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

namespace fh {
namespace {

constexpr uint32_t MAX_BINS = 256;

// x, y, z and a spare lane in one SIMD register (a GCC/Clang vector type): growing a box is two instructions where
// glm::vec3 took six, and binning, the build's inner loop, grows three boxes per triangle.
typedef float Lanes __attribute__((vector_size(16)));
constexpr float INF = std::numeric_limits<float>::infinity();

// glm::min and glm::max lane by lane, with their operand order (so that the same zero's sign wins).
Lanes min_lanes(Lanes x, Lanes y) { return y < x ? y : x; }
Lanes max_lanes(Lanes x, Lanes y) { return x < y ? y : x; }
Lanes to_lanes(const glm::vec3& p) { return Lanes{p.x, p.y, p.z, 0.0f}; }
glm::vec3 to_vec3(Lanes v) { return glm::vec3(v[0], v[1], v[2]); }

// Lane 3 is not part of the box (PrimRef keeps the triangle's index there).
struct Box {
    Lanes lo = {INF, INF, INF, INF};
    Lanes hi = {-INF, -INF, -INF, -INF};

    void grow(Lanes p) {
        lo = min_lanes(lo, p);
        hi = max_lanes(hi, p);
    }
    void grow(const Box& b) {
        lo = min_lanes(lo, b.lo);
        hi = max_lanes(hi, b.hi);
    }
    // Half the surface area (the factor 2 cancels in every SAH ratio); 0 for an empty box.
    double half_area() const {
        if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) return 0.0;
        const glm::dvec3 d = glm::dvec3(to_vec3(hi)) - glm::dvec3(to_vec3(lo));
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

// One triangle's bounds and its original index (in the low corner's spare lane: 32 bytes, two SIMD loads); these are
// partitioned in place while building. The index is kept as the bits of a normal float, INDEX_BITS + index for an
// index below 2^30 (check_input): as a plain integer it would be a denormal, and arithmetic on denormals, which the
// spare lane goes through unused, is microcoded on x86 (it made the build 2.5x slower).
constexpr uint32_t INDEX_BITS = 0x20000000u;
constexpr uint32_t MAX_PRIMITIVES = 1u << 30;
struct PrimRef {
    Box bounds;
    uint32_t triangle() const { return std::bit_cast<uint32_t>(bounds.lo[3]) - INDEX_BITS; }
    // After the box is grown: growing takes the spare lane's minimum.
    void set_triangle(uint32_t t) { bounds.lo[3] = std::bit_cast<float>(INDEX_BITS + t); }
    Lanes centroid() const { return 0.5f * (bounds.lo + bounds.hi); }
};

// A range's box and the box of its centroids.
struct RangeBounds {
    Box bounds, centroids;
    void take(const PrimRef& r, Lanes centroid) {
        bounds.grow(r.bounds);
        centroids.grow(centroid);
    }
};

RangeBounds bound_range(const std::vector<PrimRef>& refs, uint32_t begin, uint32_t end) {
    RangeBounds b;
    for (uint32_t i = begin; i < end; ++i) b.take(refs[i], refs[i].centroid());
    return b;
}

struct Task {
    uint32_t begin, end;   // range of PrimRefs
    uint32_t parent;       // node whose child_or_first must point here (second children), else INVALID_INDEX
    uint32_t depth;
    RangeBounds range;     // of refs[begin, end): the parent's partition measured it
};

struct Split {
    int axis = -1;         // -1: no split with both sides non-empty
    uint32_t last_left_bin = 0;
    double cost = std::numeric_limits<double>::infinity();  // sum of half_area * count over both sides
};

// Maps a centroid coordinate to its bin (Wald 2007 eq. 4: k1 = K (1 - eps) / extent). The same float
// arithmetic is used for binning and for partitioning, so both agree on every triangle.
struct Binner {
    Lanes origin, scale;
    uint32_t count;
    uint32_t bin(Lanes c, int axis) const { return clamp_bin((c[axis] - origin[axis]) * scale[axis]); }
    // The same for the three axes at once: lane by lane the same float operations.
    Lanes bin_coordinates(Lanes c) const { return (c - origin) * scale; }
    uint32_t clamp_bin(float f) const { return std::min(count - 1, uint32_t(std::max(f, 0.0f))); }
};

struct Bin {
    Box bounds;
    uint32_t count = 0;
};
// Empty between calls of find_split: it empties the bins it filled, not all of them (clearing all 3 x 16 bins of 48
// bytes for each of the 1.31 M-triangle mesh's million small nodes stored about 3 GB). Binning also sets each filled
// bin's bit in `used`, so the sweeps visit the bins in use without scanning all of them (a scan's branch on each bin's
// count was a fifth of the build).
struct BinScratch {
    std::array<std::array<Bin, MAX_BINS>, 3> bins;
    std::array<std::array<uint64_t, MAX_BINS / 64>, 3> used{};
};

Split find_split(const std::vector<PrimRef>& refs, const Task& task, const Box& centroids, const Binner& binner,
                 BinScratch& scratch) {
    for (uint32_t i = task.begin; i < task.end; ++i) {
        const Lanes f = binner.bin_coordinates(refs[i].centroid());
        for (int axis = 0; axis < 3; ++axis) {
            const uint32_t bin = binner.clamp_bin(f[axis]);
            Bin& b = scratch.bins[axis][bin];
            b.bounds.grow(refs[i].bounds);
            ++b.count;
            scratch.used[axis][bin / 64] |= uint64_t(1) << (bin % 64);
        }
    }
    Split best;
    const uint32_t k = binner.count;
    for (int axis = 0; axis < 3; ++axis) {
        std::array<Bin, MAX_BINS>& axis_bins = scratch.bins[axis];
        // Only the bins in use, in order. An empty bin changes neither side: the split after it costs what the split
        // before it costs, which the strict < below already preferred. So the sweeps skip empty bins (most bins of a
        // small node) with the same result, and the bins in use are all that need emptying.
        std::array<uint32_t, MAX_BINS> used;
        uint32_t used_count = 0;
        for (uint32_t word = 0; word * 64 < k; ++word) {
            for (uint64_t bits = scratch.used[axis][word]; bits != 0; bits &= bits - 1)
                used[used_count++] = word * 64 + uint32_t(std::countr_zero(bits));
            scratch.used[axis][word] = 0;
        }
        if (centroids.hi[axis] > centroids.lo[axis]) {
            // Sweep from the right to get the cost of every right side, then from the left (Wald 2007 sec. 3.2).
            std::array<double, MAX_BINS> right_cost;  // [u]: cost of the bins in use after used[u] (-1: none)
            right_cost[used_count - 1] = -1.0;
            Box right;
            uint32_t right_count = 0;
            for (uint32_t u = used_count - 1; u > 0; --u) {
                right.grow(axis_bins[used[u]].bounds);
                right_count += axis_bins[used[u]].count;
                right_cost[u - 1] = right.half_area() * right_count;
            }
            Box left;
            uint32_t left_count = 0;
            for (uint32_t u = 0; u + 1 < used_count; ++u) {
                left.grow(axis_bins[used[u]].bounds);
                left_count += axis_bins[used[u]].count;
                const double cost = left.half_area() * left_count + right_cost[u];
                if (cost < best.cost) {
                    best.axis = axis;
                    best.last_left_bin = used[u];
                    best.cost = cost;
                }
            }
        }
        for (uint32_t u = 0; u < used_count; ++u) axis_bins[used[u]] = Bin{};
    }
    return best;
}

void check_input(std::span<const glm::vec3> positions, const BvhOptions& options) {
    if (positions.empty() || positions.size() % 3 != 0)
        throw std::invalid_argument("bvh.cpp: need a positive multiple of 3 positions, got " +
                                    std::to_string(positions.size()));
    if (positions.size() / 3 > MAX_PRIMITIVES)
        throw std::invalid_argument("bvh.cpp: " + std::to_string(positions.size() / 3) + " triangles; at most 2^30");
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
    node.min_x = b.lo[0];
    node.min_y = b.lo[1];
    node.min_z = b.lo[2];
    node.max_x = b.hi[0];
    node.max_y = b.hi[1];
    node.max_z = b.hi[2];
}

// How a node is built: its box, and where its range is split (axis < 0: it is a leaf).
struct NodeSplit {
    Box bounds;
    double area = 0.0;
    int axis = -1;
    uint32_t mid = 0;
    RangeBounds first, second;  // of the two children's ranges, for a split
};

// std::partition as libstdc++ does it for bidirectional iterators (the same swaps, so the same order as before),
// measuring both sides on the way: the children's bounds cost no pass of their own.
template <typename Pred>
uint32_t partition_measuring(std::vector<PrimRef>& refs, uint32_t first, uint32_t last, Pred pred, RangeBounds& left,
                             RangeBounds& right) {
    while (true) {
        while (true) {
            if (first == last) return first;
            const Lanes c = refs[first].centroid();
            if (!pred(c)) break;
            left.take(refs[first], c);
            ++first;
        }
        // refs[first] goes right.
        --last;
        while (true) {
            if (first == last) {
                right.take(refs[first], refs[first].centroid());
                return first;
            }
            const Lanes c = refs[last].centroid();
            if (pred(c)) break;
            right.take(refs[last], c);
            --last;
        }
        std::swap(refs[first], refs[last]);
        left.take(refs[first], refs[first].centroid());
        right.take(refs[last], refs[last].centroid());
        ++first;
    }
}

// Bounds the task's range and chooses: leaf, SAH split, or median split (coincident centroids or a zero-area
// box), partitioning the range in place for a split.
NodeSplit split_node(std::vector<PrimRef>& refs, const Task& task, const BvhOptions& options, BinScratch& bins) {
    NodeSplit out;
    out.bounds = task.range.bounds;
    const Box& centroids = task.range.centroids;
    out.area = out.bounds.half_area();
    out.mid = task.begin;
    const uint32_t count = task.end - task.begin;
    if (count <= 1) return out;
    int& axis = out.axis;
    uint32_t& mid = out.mid;
    if (out.area > 0.0) {
        const glm::vec3 extent = to_vec3(centroids.hi - centroids.lo);
        Binner binner{centroids.lo, Lanes{0.0f, 0.0f, 0.0f, 0.0f}, options.bin_count};
        for (int a = 0; a < 3; ++a)
            binner.scale[a] = extent[a] > 0.0f ? float(options.bin_count) * (1.0f - 1e-6f) / extent[a] : 0.0f;
        const Split split = find_split(refs, task, centroids, binner, bins);
        const double leaf_cost = SAH_TRIANGLE_COST * count;
        const double split_cost = SAH_NODE_COST + SAH_TRIANGLE_COST * split.cost / out.area;
        const bool prefer_leaf = split.axis < 0 || leaf_cost <= split_cost;
        if (split.axis >= 0 && !(prefer_leaf && count <= options.max_leaf_size)) {
            axis = split.axis;
            const uint32_t last = split.last_left_bin;
            mid = partition_measuring(
                refs, task.begin, task.end, [&](Lanes c) { return binner.bin(c, axis) <= last; }, out.first,
                out.second);
        }
    }
    // Children may hold at most max_leaf_size * 2^(levels left below them) triangles, so that median splits from
    // there on still end within max_depth.
    const uint32_t levels_left = options.max_depth - std::min(options.max_depth, task.depth + 1);
    const double child_capacity = double(options.max_leaf_size) * std::ldexp(1.0, int(std::min(levels_left, 40u)));
    const bool too_deep = axis >= 0 && double(std::max(mid - task.begin, task.end - mid)) > child_capacity;
    if ((axis < 0 && count > options.max_leaf_size) || too_deep) {
        // Object median along the longest centroid axis (or box side when the centroids coincide).
        const glm::vec3 cd = to_vec3(centroids.hi - centroids.lo);
        const glm::vec3 d = cd == glm::vec3(0.0f) ? to_vec3(out.bounds.hi - out.bounds.lo) : cd;
        axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
        mid = task.begin + count / 2;
        std::nth_element(refs.begin() + task.begin, refs.begin() + mid, refs.begin() + task.end,
                         [a = axis](const PrimRef& l, const PrimRef& r) {
                             const float cl = l.centroid()[a], cr = r.centroid()[a];
                             return cl < cr || (cl == cr && l.triangle() < r.triangle());
                         });
        out.first = bound_range(refs, task.begin, mid);
        out.second = bound_range(refs, mid, task.end);
    }
    return out;
}

// The nodes of one subtree in depth-first order, indexed from its root at 0, with its share of the statistics.
struct Subtree {
    std::vector<gpu::BvhNode> nodes;
    double root_area = 0.0;
    double weighted_cost = 0.0;  // sum over nodes of half_area * cost of the node itself
    uint32_t leaf_count = 0;
    uint32_t max_depth = 0;
};

// Builds the subtree of one task on this thread.
Subtree build_serially(std::vector<PrimRef>& refs, const Task& root, const BvhOptions& options) {
    Subtree out;
    out.nodes.reserve(2 * size_t(root.end - root.begin));
    auto bins = std::make_unique<BinScratch>();
    std::vector<Task> stack{{root.begin, root.end, gpu::INVALID_INDEX, root.depth, root.range}};
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        const uint32_t node_index = uint32_t(out.nodes.size());
        out.nodes.emplace_back();
        if (task.parent != gpu::INVALID_INDEX) out.nodes[task.parent].child_or_first = node_index;
        const NodeSplit split = split_node(refs, task, options, *bins);
        if (node_index == 0) out.root_area = split.area;
        gpu::BvhNode& node = out.nodes[node_index];
        write_bounds(node, split.bounds);
        if (split.axis < 0) {
            const uint32_t count = task.end - task.begin;
            node.child_or_first = task.begin;
            node.count_and_axis = count;
            out.weighted_cost += split.area * SAH_TRIANGLE_COST * count;
            ++out.leaf_count;
            out.max_depth = std::max(out.max_depth, task.depth);
        } else {
            node.count_and_axis = uint32_t(split.axis) << gpu::BVH_LEAF_COUNT_BITS;
            out.weighted_cost += split.area * SAH_NODE_COST;
            // The first child is visited next, so it lands at node_index + 1 (depth-first layout).
            stack.push_back({split.mid, task.end, node_index, task.depth + 1, split.second});
            stack.push_back({task.begin, split.mid, gpu::INVALID_INDEX, task.depth + 1, split.first});
        }
    }
    return out;
}

// Ranges smaller than this are not offered to another thread (2,048 built the 20,490-triangle mesh about 7% faster
// than 4,096; 1,024 no faster).
constexpr uint32_t PARALLEL_MIN_TRIANGLES = 1u << 11;

// A subtree as the threads built it: one thread's nodes (`serial`), or a node over two parts. Laid out once at the
// end (lay_out), so no node is copied twice.
struct Part {
    Subtree serial;
    NodeSplit split;  // the node over `first` and `second`
    std::unique_ptr<Part> first, second;
};

// Builds the task's subtree, offering the second subtree of each of the top `levels` splits to the helper threads.
std::unique_ptr<Part> build_in_parallel(std::vector<PrimRef>& refs, const Task& task, const BvhOptions& options,
                                        uint32_t levels, HelperThreads& helpers) {
    auto part = std::make_unique<Part>();
    if (levels == 0 || task.end - task.begin < PARALLEL_MIN_TRIANGLES) {
        part->serial = build_serially(refs, task, options);
        return part;
    }
    {
        auto bins = std::make_unique<BinScratch>();
        part->split = split_node(refs, task, options, *bins);
    }
    const NodeSplit& split = part->split;
    if (split.axis < 0) {
        part->serial = build_serially(refs, task, options);
        return part;
    }
    const Task first{task.begin, split.mid, gpu::INVALID_INDEX, task.depth + 1, split.first};
    const Task second{split.mid, task.end, gpu::INVALID_INDEX, task.depth + 1, split.second};
    // The children own disjoint ranges of refs, so two threads never touch the same element.
    helpers.run_both([&] { part->first = build_in_parallel(refs, first, options, levels - 1, helpers); },
                     [&] { part->second = build_in_parallel(refs, second, options, levels - 1, helpers); });
    return part;
}

// Appends the part's nodes depth first (a node, its first subtree, its second) and adds up its statistics.
void lay_out(const Part& part, Subtree& out) {
    if (!part.first) {
        const uint32_t offset = uint32_t(out.nodes.size());
        if (offset == 0) out.root_area = part.serial.root_area;
        for (gpu::BvhNode node : part.serial.nodes) {
            if (leaf_count(node) == 0) node.child_or_first += offset;  // a leaf's first triangle is already global
            out.nodes.push_back(node);
        }
        out.weighted_cost += part.serial.weighted_cost;
        out.leaf_count += part.serial.leaf_count;
        out.max_depth = std::max(out.max_depth, part.serial.max_depth);
        return;
    }
    const size_t root = out.nodes.size();
    if (root == 0) out.root_area = part.split.area;
    gpu::BvhNode node{};
    write_bounds(node, part.split.bounds);
    node.count_and_axis = uint32_t(part.split.axis) << gpu::BVH_LEAF_COUNT_BITS;
    out.nodes.push_back(node);
    out.weighted_cost += part.split.area * SAH_NODE_COST;
    lay_out(*part.first, out);
    out.nodes[root].child_or_first = uint32_t(out.nodes.size());
    lay_out(*part.second, out);
}

size_t count_nodes(const Part& part) {
    return part.first ? 1 + count_nodes(*part.first) + count_nodes(*part.second) : part.serial.nodes.size();
}

Bvh build_from_refs(std::vector<PrimRef> refs, const BvhOptions& options,
                    std::chrono::steady_clock::time_point start) {
    const uint32_t triangle_count = uint32_t(refs.size());
    const Task root{0, triangle_count, gpu::INVALID_INDEX, 0, bound_range(refs, 0, triangle_count)};
    // The calling thread builds too: one helper fewer than the hardware's threads.
    const uint32_t hardware = std::max(1u, std::thread::hardware_concurrency());
    HelperThreads helpers(options.parallel_levels > 0 ? hardware - 1 : 0);
    const std::unique_ptr<Part> parts = build_in_parallel(refs, root, options, options.parallel_levels, helpers);
    Subtree tree;
    tree.nodes.reserve(count_nodes(*parts));
    lay_out(*parts, tree);
    Bvh bvh;
    bvh.nodes = std::move(tree.nodes);
    bvh.leaf_count = tree.leaf_count;
    bvh.max_depth = tree.max_depth;
    bvh.max_leaf_size = options.max_leaf_size;
    bvh.triangle_order.resize(triangle_count);
    for (uint32_t i = 0; i < triangle_count; ++i) bvh.triangle_order[i] = refs[i].triangle();
    // A scene whose root box has no area (all triangles on one line or point) reports unnormalized cost.
    bvh.sah_cost = tree.root_area > 0.0 ? tree.weighted_cost / tree.root_area : tree.weighted_cost;
    bvh.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace

Bvh build_bvh(std::span<const glm::vec3> positions, const BvhOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check_input(positions, options);
    std::vector<PrimRef> refs(positions.size() / 3);
    for (uint32_t t = 0; t < refs.size(); ++t) {
        for (int k = 0; k < 3; ++k) refs[t].bounds.grow(to_lanes(positions[3 * size_t(t) + k]));
        refs[t].set_triangle(t);
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
        refs[i].bounds.grow(to_lanes(corners[2 * size_t(i)]));
        refs[i].bounds.grow(to_lanes(corners[2 * size_t(i) + 1]));
        refs[i].set_triangle(i);
    }
    return build_from_refs(std::move(refs), options, start);
}

}  // namespace fh
