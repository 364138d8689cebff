// The light tree NEE descends with `--light-sampler tree` (Conty Estevez & Kulla 2018, "Importance Sampling of Many
// Lights with Adaptive Tree Splitting"; pbrt-v4's BVHLightSampler): a binary tree over every light that has a place,
// each node bounding its lights' positions, power and emitting directions (layout.h LightTreeNode). The device picks
// a child by its importance at the shading point (shaders/lib/light/light_tree.glsl), so a small bright lamp near the point
// is sampled as often as it matters, not in proportion to its share of the scene's total power.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/layout.h"

namespace fh {

// What bounds one light, or a set of lights: where, how much, and in which directions it emits. Every emitting
// normal lies within theta_o of `axis`, and light leaves within theta_e beyond that (pi/2: a Lambertian surface).
struct LightBounds {
    glm::dvec3 lo{0.0}, hi{0.0};
    double power = 0.0;
    glm::dvec3 axis{0.0, 0.0, 1.0};
    double cos_theta_o = 1.0;
    double cos_theta_e = 0.0;
    bool two_sided = false;
};

// The bounds of two sets together: the box and cone around both (pbrt-v4 Union of DirectionCones), power summed.
LightBounds join(const LightBounds& a, const LightBounds& b);

// A triangle emitting from its front face (winding normal), or both.
LightBounds triangle_light_bounds(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2, double power,
                                  bool two_sided);
// A point light (emits in all directions) or a spot light (full inside cos_inner, none outside cos_outer).
LightBounds punctual_light_bounds(const gpu::PunctualLight& light, double power);

struct LightTree {
    std::vector<gpu::LightTreeNode> nodes;  // interior nodes, then leaf k for light k (layout.h LightTreeNode)
    uint32_t depth = 0;                     // of the deepest leaf (the root alone: 0)
    double build_seconds = 0.0;
};

// Builds the tree over `lights` (leaf k for lights[k]): each node splits its lights where the surface-area-orientation
// heuristic (pbrt-v4 EvaluateCost: power x the cone's solid-angle measure x box area) is least, over 12 bins of the
// centroids per axis, or at the median where that is all it can do or where the depth must stay within
// LIGHT_TREE_MAX_DEPTH. Deterministic. Throws std::invalid_argument for no lights or more than MAX_TREE_LIGHTS.
LightTree build_light_tree(const std::vector<LightBounds>& lights);

// The node's bounds as the device reads them: the box rounded outwards to float, the cone widened to cover the
// rounding of its axis.
gpu::LightTreeNode make_light_tree_node(const LightBounds& b);

}  // namespace fh
