// The scene's acceleration structure as the GPU traverses it: one BVH over the world triangles, or, for a scene
// with instances, a two-level BVH (one BVH per mesh, stored once, and one over the instances' boxes).
#pragma once
#include <cstdint>
#include <vector>

#include "scene/bvh/bvh.h"
#include "scene/scene.h"
#include "shared/layout.h"

namespace fh {

struct SceneBvh {
    std::vector<gpu::BvhWideNode> nodes;       // root at 0 (the top level when instanced), meshes' after (wide_bvh.h)
    std::vector<uint32_t> triangle_order;      // leaf order -> scene triangle
    std::vector<gpu::Instance> instances;      // empty: one level
    double sah_cost = 0.0;                     // of the one level, or of the top level
    double wide_sah_cost = 0.0;                // the same of the wide nodes (wide_bvh.h)
    size_t node_count = 0;                     // BvhNodes built, over every level
    uint32_t max_depth = 0;                    // deepest binary leaf, top level and mesh level together
    uint32_t stack_bound = 0;                  // traversal stack entries the wide tree can need (wide_bvh.h)
    glm::vec3 bounds_lo{0.0f}, bounds_hi{0.0f};  // the root's box (render space)
    double build_seconds = 0.0;
};

// One level, as the GPU reads `bvh` (built over every triangle of a scene without instances).
SceneBvh make_single_level(const Bvh& bvh);

// One level for a scene without instances; two otherwise: the world triangles (if any) become one more mesh
// placed by an identity instance, so that every top-level leaf is an instance. Instance boxes are the mesh
// BVH's root box mapped by the instance (in double, rounded outwards). Throws std::invalid_argument as
// build_bvh does.
SceneBvh build_scene_bvh(const Scene& scene, const BvhOptions& options);

}  // namespace fh
