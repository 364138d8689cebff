// The Flattener, which walks the nodes of one glTF scene and flattens its meshes, cameras and lights into a Scene.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "shared/layout.h"

#include "scene/scene.h"

namespace tinygltf {
class Model;
class Node;
class Value;
struct Primitive;
}  // namespace tinygltf

namespace fh::gltf {

// A node with several parents is drawn once per path from the root (instancing; glTF itself requires the
// nodes to form disjoint trees). Sharing can multiply: 40 nodes that each list the next twice make 2^40
// paths, so the walk stops at this many node instances, and the flattened scene at this many triangles
// (about 5 GB on the host; the device limits in render/memory_estimate.h are usually far lower).
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
constexpr size_t MAX_NODE_INSTANCES = size_t(1) << 22;
constexpr size_t MAX_SCENE_TRIANGLES = size_t(1) << 26;
#else
// The fuzz build (tests/fuzz) gives each input 10 s and 2 GiB and runs ~10x slower under its sanitizers: a
// 1 KB file that merely reaches the limits above (1.4 s in release) would read as a finding there.
constexpr size_t MAX_NODE_INSTANCES = size_t(1) << 16;
constexpr size_t MAX_SCENE_TRIANGLES = size_t(1) << 20;
#endif

// The node's local transform: its matrix, or T * R * S (spec 3.5.2), in double precision.
glm::dmat4 local_transform(const tinygltf::Node& node);

// "node 3 'name'" for messages (the name where the node has one).
std::string describe_node(const tinygltf::Model& model, int index);

// True when every component is finite.
bool is_finite(const glm::vec3& v);
bool is_finite(const glm::dvec3& v);
bool is_finite(const glm::dmat4& m);

// Where a node draws: its world transform (at the render's time, or the shutter's centre) and, for motion blur, at
// the shutter's keys (SceneInstance::keys; empty for a node that stands still).
struct Placement {
    glm::dmat4 world;
    std::vector<glm::dmat4> keys;
    bool moves() const { return !keys.empty(); }
};

// The rotation that turns the axes of `open` into those of `close` (each transform's columns normalised: rotation and
// scale without shear), on the shorter arc: a unit quaternion with w >= 0.
glm::dquat find_turn(const glm::dmat4& open, const glm::dmat4& close);

// The angle (radians) of the rotation `turn` (a unit quaternion, as find_turn gives).
double turn_angle(const glm::dquat& turn);

// Flattens the nodes of one scene into `scene`. Its methods are defined in gltf_flattener.cpp (the node walk and
// instancing), gltf_primitives.cpp (meshes and their primitives) and gltf_cameras_lights.cpp.
class Flattener {
public:
    Flattener(const tinygltf::Model& model, Scene& scene, int variant);

    // World transform of every node reached from the roots (the first path where a node is shared), the joints'
    // included: skins need them before the walk reaches the joints.
    void compute_node_worlds(const std::vector<int>& roots);

    // Motion blur: the nodes' local transforms at the shutter's keys (the model posed at each: locals[key][node]);
    // without them every node keeps its transform over the shutter.
    void set_shutter_transforms(std::vector<std::vector<glm::dmat4>> locals) { local_keys_ = std::move(locals); }

    // LoadOptions::mikktspace_tangents: tangents for primitives without TANGENT whose material needs them.
    void set_generate_tangents(bool generate) { generate_tangents_ = generate; }

    // parent_keys: the parent's world transforms at the shutter's keys (set_shutter_transforms; identities at a root).
    // `visible`: no ancestor is hidden by KHR_node_visibility (a hidden node's meshes and lights, and its
    // descendants', are left out; cameras stay).
    void visit_node(int index, const glm::dmat4& parent_world, int depth, const std::vector<glm::dmat4>& parent_keys,
                    bool visible = true);

    // Places the triangles in render space (LoadOptions::rebase) and drops those without area there.
    void finish(bool rebase, Instancing instancing);

private:
    // The attributes of one primitive's vertices that textures and vertex colours read (empty if absent).
    struct VertexAttributes {
        std::vector<glm::vec4> texcoords0, texcoords1, colors, tangents;
    };

    // gltf_flattener.cpp: triangles placed in render space; mesh uses recorded during the walk, added after it.
    void place_triangles(const glm::dvec3& origin);
    void warn_once(const std::string& message) {
        if (warned_.emplace(message, 1).second) scene_.warnings.push_back(message);
    }
    void record_mesh_uses(const tinygltf::Node& node, int index, const Placement& place);
    size_t estimate_triangles(int mesh_index) const;
    bool mesh_emits(int mesh_index);
    void add_recorded_meshes(Instancing instancing);
    std::string geometry_key(int mesh_index);
    bool deforms(int mesh_index) const;

    // gltf_primitives.cpp: a mesh's primitives read, morphed and skinned into world-space triangles.
    void add_mesh(int mesh_index, const glm::dmat4& world, int node);
    uint32_t material_index(int material, const std::string& where);
    void add_primitive(const tinygltf::Primitive& prim, int mesh_index, int prim_index, const glm::dmat4& node_world,
                       int node);
    void apply_morph_targets(const tinygltf::Primitive& prim, int mesh_index, int node, const std::string& where,
                             std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
                             std::vector<glm::vec4>& tangents);
    void apply_skin(const tinygltf::Primitive& prim, int node, const std::string& where,
                    std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
                    std::vector<glm::vec4>& tangents);
    static void rotate_to_lowest_vertex(std::array<uint32_t, 3>& tri, const std::vector<glm::vec3>& positions);
    int variant_material(const tinygltf::Primitive& prim) const;
    std::vector<glm::vec3> read_vec3(int accessor, const std::string& role);
    VertexAttributes read_attributes(const tinygltf::Primitive& prim, size_t vertex_count, const std::string& where);
    // `generated`: MikkTSpace corner tangents of the triangle (gltf_tangents.h) in `generated_order`, used where the
    // primitive has no TANGENT; nullptr: none.
    void add_triangle_attributes(const VertexAttributes& a, const std::array<uint32_t, 3>& tri, const glm::dmat3& linear,
                                 bool mirrored, const std::array<glm::vec4, 3>* generated,
                                 const std::array<uint32_t, 3>& generated_order);
    // The TEXCOORD set a material's tangent frame follows (its normal, clear-coat normal or anisotropy texture's; 0
    // for anisotropy without a texture), or -1 when it needs no tangents.
    int tangent_texcoord_set(uint32_t material) const;

    // gltf_cameras_lights.cpp
    void add_camera(int camera_index, int node_index, const Placement& place);
    void add_light(const tinygltf::Value& extension, int node_index, const glm::dmat4& world);

    bool generate_tangents_ = true;
    const tinygltf::Model& model_;
    Scene& scene_;
    std::vector<glm::dvec3> world_positions_;  // 3 per triangle, until finish() places them in render space
    std::vector<glm::vec3> normals_;
    bool keep_attributes_ = false;  // the file has textures or vertex colours
    bool quantized_ = false;        // KHR_mesh_quantization is used
    std::set<std::array<int, 3>> geometry_seen_;  // primitives' geometry counted in Scene::unique_triangle_count
    int variant_ = -1;              // KHR_materials_variants index chosen (-1: the default materials)
    std::vector<glm::vec2> texcoords0_, texcoords1_;  // 3 per triangle, like normals_
    std::vector<glm::vec4> colors_, tangents_;
    std::vector<uint32_t> triangle_material_;
    std::vector<uint8_t> triangle_has_normals_;
    size_t dropped_degenerate_ = 0;
    std::vector<uint8_t> on_path_;  // 1 while a node is an ancestor of the one being visited
    uint32_t default_material_ = gpu::INVALID_INDEX;
    std::map<std::string, size_t> skipped_modes_;
    std::map<std::string, int> warned_;
    size_t dropped_nonfinite_ = 0;
    size_t flat_nonfinite_normals_ = 0;
    size_t instances_ = 0;
    size_t leftover_indices_ = 0;
    struct MeshUse {
        int mesh;
        Placement place;
        int node;  // whose skin and morph weights deform it
    };
    std::vector<MeshUse> uses_;  // in walk order
    std::vector<glm::dmat4> node_world_;  // compute_node_worlds
    std::set<int> skinned_meshes_;        // meshes drawn by a node with a skin
    size_t world_triangle_end_ = std::numeric_limits<size_t>::max();  // before dropping: object space from here
    std::vector<std::pair<size_t, size_t>> pending_meshes_;         // before dropping: [first, end) triangles
    struct PendingInstance {
        uint32_t mesh;      // pending mesh
        Placement place;
        uint32_t material;  // SceneInstance::material
    };
    std::vector<std::vector<glm::dmat4>> local_keys_;  // set_shutter_transforms
    std::vector<PendingInstance> pending_instances_;
};

}  // namespace fh::gltf
