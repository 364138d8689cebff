// Two-level BVH: mesh BVHs built once, instances placed over them (layout.h Instance, traverse.glsl).
#include "scene/bvh/scene_bvh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>

#include "scene/pack.h"
#include "scene/bvh/wide_bvh.h"

namespace fh {
namespace {

// Rows of the 3x4 affine part of `m` (column-major glm).
void write_rows(const glm::dmat4& m, gpu::vec4& r0, gpu::vec4& r1, gpu::vec4& r2) {
    gpu::vec4* rows[3] = {&r0, &r1, &r2};
    for (int r = 0; r < 3; ++r) *rows[r] = gpu::vec4(float(m[0][r]), float(m[1][r]), float(m[2][r]), float(m[3][r]));
}

// The box of the mesh's root box mapped by the instance (a moving one: by each of its keys; every point moves along
// segments between them, so their union bounds the motion), in double, rounded outwards to float.
// A moving instance's box gets a further 2^-16 of its largest coordinate: the GPU interpolates its transform and
// inverts it in float.
void map_box(const SceneInstance& instance, const gpu::BvhNode& root, glm::vec3& lo, glm::vec3& hi) {
    glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
    const std::vector<glm::dmat4> maps = instance.moves() ? instance.keys : std::vector{instance.render_from_object};
    for (const glm::dmat4& m : maps)
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? root.max_x : root.min_x, (c & 2) ? root.max_y : root.min_y,
                               (c & 4) ? root.max_z : root.min_z);
            const glm::dvec3 q = glm::dvec3(m * glm::dvec4(p, 1.0));
            a = glm::min(a, q);
            b = glm::max(b, q);
        }
    if (instance.moves()) {
        const glm::dvec3 far = glm::max(glm::abs(a), glm::abs(b));
        const double pad = std::ldexp(std::max({far.x, far.y, far.z}), -16);
        a -= pad;
        b += pad;
    }
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::nextafter(float(a[k]), -std::numeric_limits<float>::infinity());
        hi[k] = std::nextafter(float(b[k]), std::numeric_limits<float>::infinity());
    }
}

// The root's box: what the scene's triangles (or instances) span, in render space.
void set_bounds(const std::vector<gpu::BvhNode>& nodes, SceneBvh& s) {
    const gpu::BvhNode& root = nodes.at(0);
    s.bounds_lo = glm::vec3(root.min_x, root.min_y, root.min_z);
    s.bounds_hi = glm::vec3(root.max_x, root.max_y, root.max_z);
}

// A tree deeper than the GPU's traversal stack would lose subtrees; no build gets near it (the binary tree's depth is
// capped at BvhOptions::max_depth and each wide level opens two binary ones), so this is an invariant, checked.
void check_stack_bound(SceneBvh& s) {
    s.stack_bound = measure_stack_bound(s.nodes, s.instances);
    if (s.stack_bound > gpu::TRAVERSAL_STACK_SIZE)
        throw std::invalid_argument("scene_bvh.cpp: the BVH needs a traversal stack of " + std::to_string(s.stack_bound) +
                                    " entries, more than the GPU's " + std::to_string(gpu::TRAVERSAL_STACK_SIZE) +
                                    " (a larger --bvh-leaf-size makes a shallower tree)");
}

}  // namespace

SceneBvh make_single_level(const Bvh& bvh) {
    const auto start = std::chrono::steady_clock::now();
    SceneBvh s;
    WideBvh wide = make_wide_nodes(bvh.nodes, bvh.max_leaf_size);
    s.nodes = std::move(wide.nodes);
    set_bounds(bvh.nodes, s);
    check_stack_bound(s);
    s.triangle_order.reserve(wide.leaf_order.size());
    for (uint32_t leaf : wide.leaf_order) s.triangle_order.push_back(bvh.triangle_order[leaf]);
    s.sah_cost = bvh.sah_cost;
    s.wide_sah_cost = wide.sah_cost;
    s.node_count = bvh.nodes.size();
    s.max_depth = bvh.max_depth;
    // The binary build and the collapse into wide nodes.
    s.build_seconds = bvh.build_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
}

SceneBvh build_scene_bvh(const Scene& scene, const BvhOptions& options) {
    if (scene.instances.empty()) return make_single_level(build_bvh(scene.positions, options));
    const auto start = std::chrono::steady_clock::now();
    // Meshes in leaf order: the world triangles first (an identity instance), then the scene's meshes.
    std::vector<SceneMesh> meshes;
    if (scene.world_triangle_count > 0) meshes.push_back({0, scene.world_triangle_count});
    const uint32_t first_scene_mesh = uint32_t(meshes.size());
    meshes.insert(meshes.end(), scene.meshes.begin(), scene.meshes.end());
    std::vector<SceneInstance> placements;  // mesh: in `meshes`
    if (scene.world_triangle_count > 0) placements.push_back({0u, glm::dmat4(1.0), gpu::INVALID_INDEX});
    for (SceneInstance i : scene.instances) {
        i.mesh += first_scene_mesh;
        placements.push_back(i);
    }

    SceneBvh s;
    std::vector<uint32_t> root_of(meshes.size()), leaf_offset(meshes.size());
    std::vector<gpu::BvhNode> roots(meshes.size());
    std::vector<gpu::BvhWideNode> mesh_nodes;
    uint32_t deepest_mesh = 0;
    for (size_t m = 0; m < meshes.size(); ++m) {
        const std::span<const glm::vec3> positions(scene.positions.data() + 3 * meshes[m].first_triangle,
                                                   3 * meshes[m].triangle_count);
        const Bvh bvh = build_bvh(positions, options);
        roots[m] = bvh.nodes[0];
        s.node_count += bvh.nodes.size();
        deepest_mesh = std::max(deepest_mesh, bvh.max_depth);
        const WideBvh wide = make_wide_nodes(bvh.nodes, bvh.max_leaf_size);
        leaf_offset[m] = uint32_t(s.triangle_order.size());
        for (uint32_t leaf : wide.leaf_order)
            s.triangle_order.push_back(uint32_t(meshes[m].first_triangle) + bvh.triangle_order[leaf]);
        root_of[m] = uint32_t(mesh_nodes.size());  // relative to the first mesh node, fixed below
        for (gpu::BvhWideNode w : wide.nodes) {
            offset_wide_node(w, root_of[m], leaf_offset[m]);
            mesh_nodes.push_back(w);
        }
    }

    std::vector<glm::vec3> corners(2 * placements.size());
    for (size_t i = 0; i < placements.size(); ++i)
        map_box(placements[i], roots[placements[i].mesh], corners[2 * i], corners[2 * i + 1]);
    BvhOptions top = options;
    top.max_leaf_size = 1;
    const Bvh tlas = build_bvh_over_boxes(corners, top);
    s.node_count += tlas.nodes.size();
    s.sah_cost = tlas.sah_cost;
    s.max_depth = tlas.max_depth + 1 + deepest_mesh;
    WideBvh top_wide = make_wide_nodes(tlas.nodes, tlas.max_leaf_size);
    s.wide_sah_cost = top_wide.sah_cost;
    s.nodes = std::move(top_wide.nodes);
    set_bounds(tlas.nodes, s);
    for (gpu::BvhWideNode& w : s.nodes) mark_instance_leaves(w);
    // Instances in the top level's leaf order: a node's instance children are consecutive.
    std::vector<SceneInstance> ordered;
    ordered.reserve(placements.size());
    for (uint32_t leaf : top_wide.leaf_order) ordered.push_back(placements[tlas.triangle_order[leaf]]);
    placements = std::move(ordered);
    const uint32_t mesh_base = uint32_t(s.nodes.size());
    for (gpu::BvhWideNode w : mesh_nodes) {
        offset_wide_node(w, mesh_base, 0);
        s.nodes.push_back(w);
    }

    s.instances.resize(placements.size());
    for (size_t i = 0; i < placements.size(); ++i) {
        gpu::Instance& inst = s.instances[i];
        inst = {};
        const SceneInstance& p = placements[i];
        write_rows(glm::inverse(p.render_from_object), inst.object_from_render_0, inst.object_from_render_1,
                   inst.object_from_render_2);
        write_rows(p.render_from_object, inst.render_from_object_0, inst.render_from_object_1, inst.render_from_object_2);
        inst.root_node = mesh_base + root_of[p.mesh];
        inst.first_triangle = leaf_offset[p.mesh];
        inst.material = p.material;
        inst.motion = gpu::INVALID_INDEX;
        if (p.moves()) {  // its keys, as records after the placements (layout.h Instance::motion)
            inst.motion = uint32_t(s.instances.size());
            for (const glm::dmat4& key : p.keys) {
                gpu::Instance record{};
                write_rows(key, record.render_from_object_0, record.render_from_object_1, record.render_from_object_2);
                record.root_node = record.first_triangle = record.material = record.motion = gpu::INVALID_INDEX;
                s.instances.push_back(record);
            }
        }
    }
    check_stack_bound(s);
    s.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
}

}  // namespace fh
