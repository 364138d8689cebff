// The Flattener's node walk and instancing: mesh uses recorded, then copied into world space or instanced.
#include "scene/gltf/gltf_flattener.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"

namespace fh::gltf {
namespace {

constexpr int MAX_NODE_DEPTH = 1024;  // deeper hierarchies are treated as malformed

// `keys` kept only where some differ from `world`.
Placement place(const glm::dmat4& world, std::vector<glm::dmat4> keys) {
    for (const glm::dmat4& k : keys)
        if (k != world) return {world, std::move(keys)};
    return {world, {}};
}

// KHR_node_visibility's visible (true when absent); throws SceneError for one that is not a boolean.
bool is_marked_visible(const tinygltf::Model& model, int index) {
    const tinygltf::Node& node = model.nodes[size_t(index)];
    const auto it = node.extensions.find("KHR_node_visibility");
    if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("visible")) return true;
    const tinygltf::Value& visible = it->second.Get("visible");
    if (!visible.IsBool())
        throw SceneError(describe_node(model, index) + ": KHR_node_visibility visible is not true or false");
    return visible.Get<bool>();
}

}  // namespace

// The node's local transform: its matrix, or T * R * S (spec 3.5.2), in double precision.
glm::dmat4 local_transform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, like glTF
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3)
        m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4)  // glTF stores x, y, z, w; glm::dquat takes w first
        m = m * glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

std::string describe_node(const tinygltf::Model& model, int index) {
    std::string s = "node " + std::to_string(index);
    if (index >= 0 && size_t(index) < model.nodes.size() && !model.nodes[size_t(index)].name.empty())
        s += " '" + model.nodes[size_t(index)].name + "'";
    return s;
}

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool is_finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// The rotation that turns the axes of `open` into those of `close` (each transform's columns normalised: rotation and
// scale without shear), on the shorter arc: a unit quaternion with w >= 0.
glm::dquat find_turn(const glm::dmat4& open, const glm::dmat4& close) {
    auto rotation_of = [](const glm::dmat4& m) {
        return glm::dmat3(glm::normalize(glm::dvec3(m[0])), glm::normalize(glm::dvec3(m[1])), glm::normalize(glm::dvec3(m[2])));
    };
    const glm::dquat turn = glm::normalize(glm::quat_cast(rotation_of(close) * glm::transpose(rotation_of(open))));
    return turn.w < 0.0 ? -turn : turn;
}

double turn_angle(const glm::dquat& turn) {
    return 2.0 * std::atan2(glm::length(glm::dvec3(turn.x, turn.y, turn.z)), turn.w);
}

Flattener::Flattener(const tinygltf::Model& model, Scene& scene, int variant)
    : model_(model), scene_(scene), variant_(variant), on_path_(model.nodes.size(), 0) {
    // Textures read texture coordinates; KHR_materials_anisotropy reads the tangent frame (TANGENT, or texture
    // coordinates to derive it from) even where it has no texture.
    keep_attributes_ = !model.textures.empty();
    for (const tinygltf::Material& material : model.materials)
        keep_attributes_ = keep_attributes_ || material.extensions.count("KHR_materials_anisotropy") != 0;
    for (const std::string& name : model.extensionsUsed) quantized_ = quantized_ || name == "KHR_mesh_quantization";
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& prim : mesh.primitives)
            keep_attributes_ = keep_attributes_ || prim.attributes.count("COLOR_0") != 0;
}

void Flattener::compute_node_worlds(const std::vector<int>& roots) {
    node_world_.assign(model_.nodes.size(), glm::dmat4(1.0));
    std::vector<uint8_t> seen(model_.nodes.size(), 0);
    std::vector<std::pair<int, glm::dmat4>> stack;
    for (int root : roots) stack.push_back({root, glm::dmat4(1.0)});
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        if (index < 0 || size_t(index) >= model_.nodes.size() || seen[size_t(index)]) continue;  // visit_node reports
        seen[size_t(index)] = 1;
        const tinygltf::Node& node = model_.nodes[size_t(index)];
        node_world_[size_t(index)] = parent * local_transform(node);
        for (int child : node.children) stack.push_back({child, node_world_[size_t(index)]});
        if (node.skin >= 0 && node.mesh >= 0) skinned_meshes_.insert(node.mesh);
    }
}

void Flattener::visit_node(int index, const glm::dmat4& parent_world, int depth,
                           const std::vector<glm::dmat4>& parent_keys, bool visible) {
    if (index < 0 || size_t(index) >= model_.nodes.size())
        throw SceneError("root " + describe_node(model_, index) + " does not exist");
    if (on_path_[size_t(index)])
        throw SceneError(describe_node(model_, index) + " is its own ancestor (cycle in the node hierarchy)");
    if (depth > MAX_NODE_DEPTH)
        throw SceneError("node hierarchy deeper than " + std::to_string(MAX_NODE_DEPTH) + " (at " +
                         describe_node(model_, index) + ")");
    if (++instances_ > MAX_NODE_INSTANCES)
        throw SceneError("the node hierarchy has more than " + std::to_string(MAX_NODE_INSTANCES) +
                         " node instances (nodes shared by several parents multiply; at " +
                         describe_node(model_, index) + ")");
    on_path_[size_t(index)] = 1;
    const tinygltf::Node& node = model_.nodes[size_t(index)];
    const glm::dmat4 world = parent_world * local_transform(node);
    std::vector<glm::dmat4> keys(local_keys_.size());
    for (size_t k = 0; k < keys.size(); ++k) keys[k] = parent_keys[k] * local_keys_[k][size_t(index)];
    // Transforms cannot be NaN in JSON, but scales and matrices can overflow when composed.
    if (!is_finite(world) || !std::all_of(keys.begin(), keys.end(), [](const glm::dmat4& m) { return is_finite(m); }))
        throw SceneError("the world transform of " + describe_node(model_, index) +
                         " is not finite (its transform or an ancestor's overflows)");
    visible = visible && is_marked_visible(model_, index);
    if (node.mesh >= 0 && visible) record_mesh_uses(node, index, place(world, keys));
    if (node.camera >= 0) add_camera(node.camera, index, place(world, keys));
    if (const auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end() && visible)
        add_light(it->second, index, world);
    for (int child : node.children) {
        if (child < 0 || size_t(child) >= model_.nodes.size())
            throw SceneError(describe_node(model_, index) + " has child " + std::to_string(child) +
                             ", which does not exist");
        visit_node(child, world, depth + 1, keys, visible);
    }
    on_path_[size_t(index)] = 0;
}

void Flattener::finish(bool rebase, Instancing instancing) {
    add_recorded_meshes(instancing);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < 3 * world_triangle_end_; ++i) {
        lo = glm::min(lo, world_positions_[i]);
        hi = glm::max(hi, world_positions_[i]);
    }
    std::vector<std::pair<glm::dvec3, glm::dvec3>> mesh_boxes;  // object space
    for (const auto& [first, end] : pending_meshes_) {
        glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
        for (size_t i = 3 * first; i < 3 * end; ++i) {
            a = glm::min(a, world_positions_[i]);
            b = glm::max(b, world_positions_[i]);
        }
        mesh_boxes.push_back({a, b});
    }
    for (const PendingInstance& i : pending_instances_) {  // the mesh's object box, mapped (at every key)
        const auto& [a, b] = mesh_boxes[i.mesh];
        std::vector<const glm::dmat4*> maps{&i.place.world};
        for (const glm::dmat4& k : i.place.keys) maps.push_back(&k);
        for (const glm::dmat4* world : maps)
            for (int c = 0; c < 8 && a.x <= b.x; ++c) {
                const glm::dvec3 q(*world * glm::dvec4((c & 1) ? b.x : a.x, (c & 2) ? b.y : a.y, (c & 4) ? b.z : a.z, 1.0));
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
            }
    }
    if (lo.x <= hi.x) {
        scene_.bounds_min = lo;
        scene_.bounds_max = hi;
        if (rebase) scene_.origin = 0.5 * (lo + hi);
    }
    place_triangles(scene_.origin);
    for (const auto& [mode, count] : skipped_modes_)
        scene_.warnings.push_back("skipped " + std::to_string(count) + " primitive(s) drawn as " + mode);
    if (dropped_nonfinite_ > 0)
        scene_.warnings.push_back("dropped " + std::to_string(dropped_nonfinite_) +
                                  " triangle(s) with NaN or infinite positions");
    if (flat_nonfinite_normals_ > 0)
        scene_.warnings.push_back("shaded " + std::to_string(flat_nonfinite_normals_) +
                                  " triangle(s) flat: NaN, infinite or zero normals");
    if (dropped_degenerate_ > 0)
        scene_.warnings.push_back("dropped " + std::to_string(dropped_degenerate_) +
                                  " triangle(s) without area (collinear or repeated vertices)");
    if (leftover_indices_ > 0)
        scene_.warnings.push_back("ignored " + std::to_string(leftover_indices_) +
                                  " trailing index(es) that do not complete a triangle");
}

// Rounds world positions (double) minus `origin` to float, keeping the triangles whose float cross
// product is not zero: the GPU could neither hit them (zero determinant) nor give them a normal.
// Instanced meshes stay in object space; their instances get the origin instead.
void Flattener::place_triangles(const glm::dvec3& origin) {
    size_t mesh = 0;  // the pending mesh the next object-space triangle belongs to
    for (size_t t = 0; t < triangle_material_.size(); ++t) {
        const bool object_space = t >= world_triangle_end_;
        if (t == world_triangle_end_) scene_.world_triangle_count = scene_.triangle_count();
        while (object_space && mesh < pending_meshes_.size() && t >= pending_meshes_[mesh].second) ++mesh;
        if (object_space && (scene_.meshes.size() <= mesh || t == pending_meshes_[mesh].first)) {
            scene_.meshes.resize(mesh + 1);
            scene_.meshes[mesh].first_triangle = scene_.triangle_count();
        }
        const glm::dvec3 shift = object_space ? glm::dvec3(0.0) : origin;
        std::array<glm::vec3, 3> p;
        for (int k = 0; k < 3; ++k) p[size_t(k)] = glm::vec3(world_positions_[3 * t + size_t(k)] - shift);
        const glm::vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
        if (!(glm::dot(c, c) > 0.0f) || !is_finite(c)) {
            ++dropped_degenerate_;
            continue;
        }
        if (object_space) ++scene_.meshes[mesh].triangle_count;
        for (int k = 0; k < 3; ++k) {
            const size_t v = 3 * t + size_t(k);
            scene_.positions.push_back(p[size_t(k)]);
            scene_.normals.push_back(normals_[v]);
            if (keep_attributes_) {
                scene_.texcoords0.push_back(texcoords0_[v]);
                scene_.texcoords1.push_back(texcoords1_[v]);
                scene_.colors.push_back(colors_[v]);
                scene_.tangents.push_back(tangents_[v]);
            }
        }
        scene_.triangle_material.push_back(triangle_material_[t]);
        scene_.triangle_has_normals.push_back(triangle_has_normals_[t]);
    }
    if (world_triangle_end_ >= triangle_material_.size()) scene_.world_triangle_count = scene_.triangle_count();
    scene_.meshes.resize(pending_meshes_.size());  // a mesh whose triangles all dropped keeps 0 of them
    const glm::dmat4 from_world = glm::translate(glm::dmat4(1.0), -origin);
    for (const PendingInstance& i : pending_instances_) {
        if (scene_.meshes[i.mesh].triangle_count == 0) continue;
        SceneInstance instance{i.mesh, from_world * i.place.world, i.material};
        if (i.place.moves()) {  // keyed, and placed where its path has it halfway
            for (const glm::dmat4& k : i.place.keys) instance.keys.push_back(from_world * k);
            instance.render_from_object = instance.render_from_object_at(0.5);
            ++scene_.moving_instances;
        }
        scene_.instances.push_back(instance);
    }
    if (scene_.instances.empty()) scene_.meshes.clear();
    world_positions_.clear();
    world_positions_.shrink_to_fit();
    for (SceneLight& light : scene_.lights) light.position -= origin;
}

// A node's mesh, once per EXT_mesh_gpu_instancing element if it has them (each placed node world x
// translation x rotation x scale), drawn after the walk (add_recorded_meshes).
void Flattener::record_mesh_uses(const tinygltf::Node& node, int index, const Placement& place) {
    const auto it = node.extensions.find("EXT_mesh_gpu_instancing");
    if (it == node.extensions.end() || !it->second.IsObject()) {
        uses_.push_back({node.mesh, place, index});
        return;
    }
    const std::string where = "EXT_mesh_gpu_instancing of " + describe_node(model_, index);
    const tinygltf::Value& attributes = it->second.Get("attributes");
    if (!attributes.IsObject()) throw SceneError(where + " has no attributes");
    std::vector<glm::vec4> columns[3];
    const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    size_t count = 0;
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        if (!attributes.Has(names[a])) continue;
        const tinygltf::Value& accessor = attributes.Get(names[a]);
        if (!accessor.IsInt() && !accessor.IsNumber()) throw SceneError(where + ": " + names[a] + " is not an accessor index");
        const int components = a == 1 ? 4 : 3;
        const int id = gltf::read_json_index(accessor);
        if (id >= 0 && size_t(id) < model_.accessors.size() && model_.accessors[size_t(id)].count > MAX_NODE_INSTANCES)
            throw SceneError(where + ": " + std::to_string(model_.accessors[size_t(id)].count) +
                             " instances take the scene past " + std::to_string(MAX_NODE_INSTANCES) + " node instances");
        columns[a] = gltf::read_vectors(model_, id, std::string(names[a]) + " of " + where,
                                        components, components, true);
        if (any && columns[a].size() != count)
            throw SceneError(where + ": " + names[a] + " has " + std::to_string(columns[a].size()) +
                             " elements, the other attributes " + std::to_string(count));
        count = columns[a].size();
        any = true;
    }
    if (!any) throw SceneError(where + " has none of TRANSLATION, ROTATION, SCALE");
    if (count > MAX_NODE_INSTANCES || instances_ + count > MAX_NODE_INSTANCES)
        throw SceneError(where + ": " + std::to_string(count) + " instances take the scene past " +
                         std::to_string(MAX_NODE_INSTANCES) + " node instances");
    instances_ += count;
    for (size_t i = 0; i < count; ++i) {
        glm::dmat4 local(1.0);
        if (!columns[0].empty()) local = glm::translate(local, glm::dvec3(glm::vec3(columns[0][i])));
        if (!columns[1].empty()) {
            const glm::dvec4 q(columns[1][i]);
            const double length = glm::length(q);
            if (!(length > 0.0) || !std::isfinite(length))
                throw SceneError(where + ": ROTATION " + std::to_string(i) + " is not a rotation (length 0 or not finite)");
            local = local * glm::mat4_cast(glm::dquat(q.w, q.x, q.y, q.z));  // as node rotations: unit by the spec
        }
        if (!columns[2].empty()) local = glm::scale(local, glm::dvec3(glm::vec3(columns[2][i])));
        Placement placed{place.world * local, place.keys};
        for (glm::dmat4& k : placed.keys) k = k * local;
        if (!is_finite(placed.world) ||
            !std::all_of(placed.keys.begin(), placed.keys.end(), [](const glm::dmat4& m) { return is_finite(m); }))
            throw SceneError(where + ": instance " + std::to_string(i) + " has a transform that is not finite");
        uses_.push_back({node.mesh, placed, index});
    }
}

// Triangles of a mesh from its accessors' counts (before anything is read or dropped).
size_t Flattener::estimate_triangles(int mesh_index) const {
    if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size()) return 0;
    size_t n = 0;
    for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives) {
        const auto position = prim.attributes.find("POSITION");
        const int accessor = prim.indices >= 0 ? prim.indices : position == prim.attributes.end() ? -1 : position->second;
        if (accessor >= 0 && size_t(accessor) < model_.accessors.size()) n += model_.accessors[size_t(accessor)].count / 3;
    }
    return n;
}

bool Flattener::mesh_emits(int mesh_index) {
    if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size()) return false;  // add_mesh reports it
    for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives) {
        const int material = variant_material(prim);
        if (material < 0 || size_t(material) >= scene_.materials.size()) continue;
        const gpu::vec4& e = scene_.materials[size_t(material)].emission;
        if (e.r > 0.0f || e.g > 0.0f || e.b > 0.0f) return true;
    }
    return false;
}

// Every recorded mesh use: copied into world space, or (instancing, a mesh placed more than once that
// emits no light: lights are picked per world-space triangle) stored once after the world triangles, in
// object space, with one instance per use.
//
// glTF meshes that list the same accessors share their geometry (MetalRoughSpheresNoTextures: 98 meshes, one
// sphere, 98 materials): they are one stored mesh, and an instance of a one-primitive mesh carries its own
// material (opaque ones only: alpha is tested during traversal with the triangle's material).
void Flattener::add_recorded_meshes(Instancing instancing) {
    std::map<std::string, int> first_with_geometry;
    std::map<int, int> stored_as;  // glTF mesh -> the glTF mesh whose geometry is stored for it
    for (const MeshUse& use : uses_)
        if (!stored_as.count(use.mesh))
            stored_as[use.mesh] = first_with_geometry.emplace(geometry_key(use.mesh), use.mesh).first->second;
    std::map<int, size_t> uses_of;
    for (const MeshUse& use : uses_) ++uses_of[stored_as[use.mesh]];
    std::map<int, uint32_t> instanced;  // stored glTF mesh -> pending mesh index
    for (const auto& [mesh, count] : uses_of) {
        if (count < 2 || instancing == Instancing::never || mesh_emits(mesh) || deforms(mesh)) continue;
        if (instancing == Instancing::always ||
            double(count - 1) * double(estimate_triangles(mesh)) >= double(MIN_TRIANGLES_SAVED_BY_INSTANCING))
            instanced.emplace(mesh, 0u);
    }
    // Motion blur: a rigid mesh that moves during the shutter is an instance (its BVH box bounds the motion), an
    // emitting one included: next-event estimation cannot sample it (lights are picked per world-space triangle),
    // so rays that hit it see its light with MIS weight 1. A deforming mesh stays where it is at the centre.
    size_t moving_emitters = 0;
    for (const MeshUse& use : uses_)
        if (use.place.moves() && !deforms(use.mesh) && instanced.emplace(stored_as[use.mesh], 0u).second &&
            mesh_emits(stored_as[use.mesh]))
            ++moving_emitters;
    if (moving_emitters > 0)
        scene_.warnings.push_back(std::to_string(moving_emitters) +
                                  " emitting mesh(es) move during the shutter: their light is found by BSDF sampling "
                                  "alone (next-event estimation samples static emitters only)");
    for (const MeshUse& use : uses_)
        if (!instanced.count(stored_as[use.mesh])) add_mesh(use.mesh, use.place.world, use.node);
    world_triangle_end_ = triangle_material_.size();
    for (auto& [mesh, pending] : instanced) {
        pending = uint32_t(pending_meshes_.size());
        const size_t begin = triangle_material_.size();
        add_mesh(mesh, glm::dmat4(1.0), -1);
        pending_meshes_.push_back({begin, triangle_material_.size()});
    }
    for (const MeshUse& use : uses_) {
        const int stored = stored_as[use.mesh];
        const auto it = instanced.find(stored);
        if (it == instanced.end()) continue;
        uint32_t material = gpu::INVALID_INDEX;
        if (use.mesh != stored) {
            const std::string where = "mesh " + std::to_string(use.mesh) + " primitive 0";
            material = material_index(variant_material(model_.meshes[size_t(use.mesh)].primitives[0]), where);
            if (material == material_index(variant_material(model_.meshes[size_t(stored)].primitives[0]), where))
                material = gpu::INVALID_INDEX;
        }
        pending_instances_.push_back({it->second, use.place, material});
    }
    uses_.clear();
}

// What makes two glTF meshes the same stored geometry: every primitive's mode, indices and attribute
// accessors, and its material unless the mesh is one primitive with an opaque, non-emitting material (an
// instance can then carry the material). Emitting meshes are never shared (mesh_emits).
std::string Flattener::geometry_key(int mesh_index) {
    if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size() || mesh_emits(mesh_index) || deforms(mesh_index))
        return "mesh " + std::to_string(mesh_index);  // add_mesh reports a missing mesh
    const tinygltf::Mesh& mesh = model_.meshes[size_t(mesh_index)];
    std::string key;
    for (const tinygltf::Primitive& prim : mesh.primitives) {
        key += "p" + std::to_string(prim.mode) + "," + std::to_string(prim.indices);
        for (const auto& [name, accessor] : prim.attributes) key += "," + name + "=" + std::to_string(accessor);
        if (!prim.targets.empty()) return "mesh " + std::to_string(mesh_index);
        const int material = variant_material(prim);
        const bool opaque = material < 0 || (size_t(material) < scene_.materials.size() &&
                                             scene_.materials[size_t(material)].alpha_mode == gpu::ALPHA_OPAQUE);
        if (mesh.primitives.size() != 1 || !opaque) key += ",m" + std::to_string(material);
        key += ";";
    }
    return key;
}

// A mesh is deformed where it has morph targets or a skinned node draws it: such meshes are copied per use.
bool Flattener::deforms(int mesh_index) const {
    if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size()) return false;
    if (skinned_meshes_.count(mesh_index)) return true;
    for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives)
        if (!prim.targets.empty()) return true;
    return false;
}

}  // namespace fh::gltf
