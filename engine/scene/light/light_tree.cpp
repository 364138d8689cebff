// build_light_tree: top-down, binned by centroid, split by pbrt-v4's surface-area-orientation heuristic.
#include "scene/light/light_tree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>

#include <glm/gtc/constants.hpp>

#include "scene/helper_threads.h"

namespace fh {
namespace {

constexpr double PI = glm::pi<double>();
constexpr int BINS = 12;

double safe_acos(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }

// The angle between two unit vectors, accurate near 0 and pi (pbrt-v4 AngleBetween).
double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    if (glm::dot(a, b) < 0.0) return PI - 2.0 * std::asin(std::min(1.0, glm::length(a + b) / 2.0));
    return 2.0 * std::asin(std::min(1.0, glm::length(b - a) / 2.0));
}

// The smallest cone around two cones (pbrt-v4 Union(DirectionCone, DirectionCone)).
void join_cones(const glm::dvec3& wa, double cos_a, const glm::dvec3& wb, double cos_b, glm::dvec3& w, double& cos_o) {
    if (wa == wb) {  // coplanar emitters (a panel's triangles, a grid of lamps): no trigonometry
        w = wa;
        cos_o = std::min(cos_a, cos_b);
        return;
    }
    const double theta_a = safe_acos(cos_a), theta_b = safe_acos(cos_b), theta_d = angle_between(wa, wb);
    w = wa;
    cos_o = cos_a;
    if (std::min(theta_d + theta_b, PI) <= theta_a) return;
    w = wb;
    cos_o = cos_b;
    if (std::min(theta_d + theta_a, PI) <= theta_b) return;
    const double theta_o = (theta_a + theta_d + theta_b) / 2.0;
    const glm::dvec3 k = glm::cross(wa, wb);
    w = wa;
    cos_o = -1.0;  // the whole sphere
    if (theta_o >= PI || glm::dot(k, k) == 0.0) return;
    const double theta_r = theta_o - theta_a;
    const glm::dvec3 axis = glm::normalize(k);  // rotate wa towards wb by theta_r (Rodrigues; axis is normal to wa)
    w = glm::normalize(wa * std::cos(theta_r) + glm::cross(axis, wa) * std::sin(theta_r));
    cos_o = std::cos(theta_o);
}

double surface_area(const LightBounds& b) {
    const glm::dvec3 d = b.hi - b.lo;
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// pbrt-v4's M_Omega: the solid-angle measure of the directions the cone emits into, weighted by cosine.
double orientation_measure(const LightBounds& b) {
    const double theta_o = safe_acos(b.cos_theta_o), theta_e = safe_acos(b.cos_theta_e);
    const double theta_w = std::min(theta_o + theta_e, PI);
    const double sin_o = std::sqrt(std::max(0.0, 1.0 - b.cos_theta_o * b.cos_theta_o));
    return 2.0 * PI * (1.0 - b.cos_theta_o) +
           PI / 2.0 * (2.0 * theta_w * sin_o - std::cos(theta_o - 2.0 * theta_w) - 2.0 * theta_o * sin_o + b.cos_theta_o);
}

glm::dvec3 centroid(const LightBounds& b) { return 0.5 * (b.lo + b.hi); }

uint32_t ceil_log2(size_t n) {
    uint32_t bits = 0;
    while ((size_t(1) << bits) < n) ++bits;
    return bits;
}

float round_down(double x) {
    float f = float(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float round_up(double x) {
    float f = float(x);
    return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Subtrees of at least this many lights are offered to the helper threads (smaller ones cost less than the hand-over).
constexpr size_t PARALLEL_LIGHTS = 4096;

class TreeBuilder {
public:
    explicit TreeBuilder(const std::vector<LightBounds>& lights)
        : lights_(lights), order_(lights.size()), leaf_base_(uint32_t(lights.size()) - 1u),
          helpers_(lights.size() >= 2 * PARALLEL_LIGHTS ? std::max(1u, std::thread::hardware_concurrency()) - 1u : 0u) {
        std::iota(order_.begin(), order_.end(), 0u);
        tree_.nodes.resize(2 * lights.size() - 1);
    }

    LightTree build() {
        tree_.depth = build_node(0, order_.size(), 0, 0, 0);
        return std::move(tree_);
    }

private:
    const std::vector<LightBounds>& lights_;
    std::vector<uint32_t> order_;
    uint32_t leaf_base_;
    HelperThreads helpers_;
    LightTree tree_;

    // Builds the subtree of order_[begin, end) at `depth` below the root along `path`; its interior nodes are
    // [interior, interior + end - begin - 1) in depth-first order, whichever thread builds which part. Returns the
    // depth of its deepest leaf.
    uint32_t build_node(size_t begin, size_t end, uint32_t depth, uint32_t path, uint32_t interior) {
        if (end - begin == 1) {
            const uint32_t light = order_[begin];
            gpu::LightTreeNode& leaf = tree_.nodes[leaf_base_ + light];
            leaf = make_light_tree_node(lights_[light]);
            leaf.child0 = path;
            leaf.child1 = depth;
            leaf.flags |= gpu::LIGHT_NODE_LEAF;
            leaf.emitter = light;
            return depth;
        }
        LightBounds all = lights_[order_[begin]];
        for (size_t i = begin + 1; i < end; ++i) all = join(all, lights_[order_[i]]);
        const size_t mid = split(begin, end, all, depth);
        const uint32_t first_interior = interior + 1, second_interior = interior + uint32_t(mid - begin);
        uint32_t first_depth = 0, second_depth = 0;
        auto first = [&] { first_depth = build_node(begin, mid, depth + 1, path, first_interior); };
        auto second = [&] { second_depth = build_node(mid, end, depth + 1, path | (1u << depth), second_interior); };
        if (std::min(mid - begin, end - mid) >= PARALLEL_LIGHTS) helpers_.run_both(first, second);
        else first(), second();
        gpu::LightTreeNode& node = tree_.nodes[interior];
        node = make_light_tree_node(all);
        node.child0 = mid - begin == 1 ? leaf_base_ + order_[begin] : first_interior;
        node.child1 = end - mid == 1 ? leaf_base_ + order_[mid] : second_interior;
        node.emitter = gpu::INVALID_INDEX;
        return std::max(first_depth, second_depth);
    }

    // Where [begin, end) splits (order_ rearranged): the least-cost bin boundary, else the median.
    size_t split(size_t begin, size_t end, const LightBounds& all, uint32_t depth) {
        glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (size_t i = begin; i < end; ++i) {
            lo = glm::min(lo, centroid(lights_[order_[i]]));
            hi = glm::max(hi, centroid(lights_[order_[i]]));
        }
        const glm::dvec3 extent = hi - lo;
        const int widest = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        // The depth must stay within the leaf's path word: past this point every split halves the count.
        const bool must_halve = depth + ceil_log2(end - begin) >= gpu::LIGHT_TREE_MAX_DEPTH;
        int best_dim = -1, best_bin = 0;
        if (!must_halve) find_best_bin(begin, end, all, lo, extent, best_dim, best_bin);
        if (best_dim < 0) return split_at_median(begin, end, widest);
        auto first_side = [&](uint32_t light) { return bin_of(lights_[light], best_dim, lo, extent) <= best_bin; };
        return size_t(std::stable_partition(order_.begin() + ptrdiff_t(begin), order_.begin() + ptrdiff_t(end),
                                            first_side) - order_.begin());
    }

    static int bin_of(const LightBounds& b, int dim, const glm::dvec3& lo, const glm::dvec3& extent) {
        const int bin = int(double(BINS) * (centroid(b)[dim] - lo[dim]) / extent[dim]);
        return std::clamp(bin, 0, BINS - 1);
    }

    void find_best_bin(size_t begin, size_t end, const LightBounds& all, const glm::dvec3& lo,
                       const glm::dvec3& extent, int& best_dim, int& best_bin) const {
        const glm::dvec3 diagonal = all.hi - all.lo;
        const double widest = std::max({diagonal.x, diagonal.y, diagonal.z});
        // Point lights have boxes of no area: a floor keeps their cost from vanishing (ties split nothing).
        const double area_floor = 1e-6 * std::max(surface_area(all), 1e-30);
        double best_cost = std::numeric_limits<double>::infinity();
        for (int dim = 0; dim < 3; ++dim) {
            if (!(extent[dim] > 0.0)) continue;
            std::array<LightBounds, BINS> bins;
            std::array<bool, BINS> used{};
            for (size_t i = begin; i < end; ++i) {
                const LightBounds& b = lights_[order_[i]];
                const int k = bin_of(b, dim, lo, extent);
                bins[size_t(k)] = used[size_t(k)] ? join(bins[size_t(k)], b) : b;
                used[size_t(k)] = true;
            }
            const double kr = widest / std::max(diagonal[dim], 1e-300);
            auto cost = [&](const LightBounds& b) {
                return b.power * orientation_measure(b) * kr * (surface_area(b) + area_floor);
            };
            // Costs of the bins left of each boundary, then sweep from the right.
            std::array<double, BINS> left_cost{};
            LightBounds left;
            bool left_used = false;
            for (int k = 0; k < BINS - 1; ++k) {
                if (used[size_t(k)]) {
                    left = left_used ? join(left, bins[size_t(k)]) : bins[size_t(k)];
                    left_used = true;
                }
                left_cost[size_t(k)] = left_used ? cost(left) : -1.0;
            }
            LightBounds right;
            bool right_used = false;
            for (int k = BINS - 1; k > 0; --k) {
                if (used[size_t(k)]) {
                    right = right_used ? join(right, bins[size_t(k)]) : bins[size_t(k)];
                    right_used = true;
                }
                if (!right_used || left_cost[size_t(k - 1)] < 0.0) continue;
                const double c = left_cost[size_t(k - 1)] + cost(right);
                if (c < best_cost) {
                    best_cost = c;
                    best_dim = dim;
                    best_bin = k - 1;
                }
            }
        }
    }

    size_t split_at_median(size_t begin, size_t end, int dim) {
        const size_t mid = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + ptrdiff_t(begin), order_.begin() + ptrdiff_t(mid), order_.begin() + ptrdiff_t(end),
                         [&](uint32_t a, uint32_t b) {
                             const double ca = centroid(lights_[a])[dim], cb = centroid(lights_[b])[dim];
                             return ca < cb || (ca == cb && a < b);
                         });
        return mid;
    }
};

}  // namespace

LightBounds join(const LightBounds& a, const LightBounds& b) {
    if (!(a.power > 0.0)) return b;
    if (!(b.power > 0.0)) return a;
    LightBounds j;
    j.lo = glm::min(a.lo, b.lo);
    j.hi = glm::max(a.hi, b.hi);
    j.power = a.power + b.power;
    join_cones(a.axis, a.cos_theta_o, b.axis, b.cos_theta_o, j.axis, j.cos_theta_o);
    j.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    j.two_sided = a.two_sided || b.two_sided;
    return j;
}

LightBounds triangle_light_bounds(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2, double power,
                                  bool two_sided) {
    LightBounds b;
    b.lo = glm::min(p0, glm::min(p1, p2));
    b.hi = glm::max(p0, glm::max(p1, p2));
    b.power = power;
    const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
    b.axis = glm::dot(n, n) > 0.0 ? glm::normalize(n) : glm::dvec3(0.0, 0.0, 1.0);
    b.cos_theta_o = 1.0;  // one normal
    b.cos_theta_e = 0.0;  // a Lambertian emitter: up to pi/2 from it
    b.two_sided = two_sided;
    return b;
}

LightBounds punctual_light_bounds(const gpu::PunctualLight& light, double power) {
    LightBounds b;
    b.lo = b.hi = glm::dvec3(light.position);
    b.power = power;
    if (light.type == gpu::LIGHT_SPOT) {  // pbrt-v4 SpotLight::Bounds: the full cone, then the falloff beyond it
        b.axis = glm::normalize(glm::dvec3(light.direction));
        const double inner = safe_acos(std::max(light.cos_inner, light.cos_outer)), outer = safe_acos(light.cos_outer);
        b.cos_theta_o = std::cos(inner);
        b.cos_theta_e = std::cos(outer - inner);
    } else {
        b.cos_theta_o = -1.0;  // every direction
        b.cos_theta_e = 0.0;
    }
    return b;
}

gpu::LightTreeNode make_light_tree_node(const LightBounds& b) {
    gpu::LightTreeNode n{};
    n.min_x = round_down(b.lo.x);
    n.min_y = round_down(b.lo.y);
    n.min_z = round_down(b.lo.z);
    n.max_x = round_up(b.hi.x);
    n.max_y = round_up(b.hi.y);
    n.max_z = round_up(b.hi.z);
    n.power = float(b.power);
    const glm::vec3 axis = glm::normalize(glm::vec3(b.axis));
    n.axis_x = axis.x;
    n.axis_y = axis.y;
    n.axis_z = axis.z;
    n.cos_theta_o = round_down(b.cos_theta_o);
    n.cos_theta_e = round_down(b.cos_theta_e);
    n.flags = b.two_sided ? gpu::LIGHT_NODE_TWO_SIDED : 0u;
    return n;
}

LightTree build_light_tree(const std::vector<LightBounds>& lights) {
    if (lights.empty()) throw std::invalid_argument("build_light_tree: no lights");
    if (lights.size() > gpu::MAX_TREE_LIGHTS)
        throw std::invalid_argument("the light tree holds at most " + std::to_string(gpu::MAX_TREE_LIGHTS) + " lights, not " +
                                    std::to_string(lights.size()));
    const auto start = std::chrono::steady_clock::now();
    LightTree tree = TreeBuilder(lights).build();
    tree.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace fh
