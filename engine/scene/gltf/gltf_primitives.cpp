// The Flattener's meshes: each primitive read (morphed, skinned, its variant's material) into world-space triangles.
#include "scene/gltf/gltf_flattener.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"
#include "scene/gltf/gltf_material.h"
#include "scene/gltf/gltf_tangents.h"
#include "scene/gltf/gltf_texture.h"

namespace fh::gltf {
namespace {

const char* mode_name(int mode) {
    switch (mode) {
        case TINYGLTF_MODE_POINTS: return "POINTS";
        case TINYGLTF_MODE_LINE: return "LINES";
        case TINYGLTF_MODE_LINE_LOOP: return "LINE_LOOP";
        case TINYGLTF_MODE_LINE_STRIP: return "LINE_STRIP";
        default: return "an unknown mode";
    }
}

// Vertex index triples of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN primitive, with the windings of
// spec 3.7.2.1 (so strips and fans keep a consistent orientation). Triangles that repeat a vertex index
// (strip restarts) are dropped: they have no area.
std::vector<std::array<uint32_t, 3>> make_triangles(int mode, const std::vector<uint32_t>& v) {
    std::vector<std::array<uint32_t, 3>> out;
    const size_t n = v.size();
    auto push = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (a != b && b != c && a != c) out.push_back({a, b, c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        out.reserve(n / 3);
        for (size_t i = 0; i + 2 < n; i += 3) push(v[i], v[i + 1], v[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < n; ++i) {
            if (i % 2 == 0) push(v[i], v[i + 1], v[i + 2]);
            else push(v[i], v[i + 2], v[i + 1]);
        }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (size_t i = 0; i + 2 < n; ++i) push(v[i + 1], v[i + 2], v[0]);
    }
    return out;
}

}  // namespace

// `node`: the node drawing the mesh (its skin and morph weights), -1 for an instanced mesh's stored copy.
void Flattener::add_mesh(int mesh_index, const glm::dmat4& world, int node) {
    if (size_t(mesh_index) >= model_.meshes.size())
        throw SceneError("mesh " + std::to_string(mesh_index) + " does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[size_t(mesh_index)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = mesh.primitives[p];
        const size_t before = triangle_material_.size();
        add_primitive(prim, mesh_index, int(p), world, node);
        // Unique triangles: a primitive's geometry (its POSITION and index accessors and mode) counted at its
        // first use, however many nodes or meshes draw it (before degenerate ones are dropped).
        const auto position = prim.attributes.find("POSITION");
        const std::array<int, 3> key{position == prim.attributes.end() ? -1 : position->second, prim.indices, prim.mode};
        if (geometry_seen_.insert(key).second) scene_.unique_triangle_count += triangle_material_.size() - before;
    }
}

uint32_t Flattener::material_index(int material, const std::string& where) {
    if (material >= 0) {
        if (size_t(material) >= model_.materials.size())
            throw SceneError("material " + std::to_string(material) + " does not exist (" + where + ")");
        return uint32_t(material);
    }
    if (default_material_ == gpu::INVALID_INDEX) {
        default_material_ = uint32_t(scene_.materials.size());
        scene_.materials.push_back(gltf::make_default_material());
        scene_.material_layers.push_back(gltf::make_default_layers());
    }
    return default_material_;
}

void Flattener::add_primitive(const tinygltf::Primitive& prim, int mesh_index, int prim_index,
                              const glm::dmat4& node_world, int node) {
    const std::string where = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(prim_index);
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        ++skipped_modes_[mode_name(mode)];
        return;
    }
    const auto position_it = prim.attributes.find("POSITION");
    if (position_it == prim.attributes.end()) throw SceneError("primitive has no POSITION (" + where + ")");
    std::vector<glm::vec3> positions = read_vec3(position_it->second, "POSITION of " + where);
    std::vector<glm::vec3> normals;
    if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        normals = read_vec3(it->second, "NORMAL of " + where);
        if (normals.size() != positions.size())
            throw SceneError("NORMAL has " + std::to_string(normals.size()) + " elements but POSITION has " +
                             std::to_string(positions.size()) + " (accessor " + std::to_string(it->second) +
                             ", " + where + ")");
    }
    VertexAttributes attributes;
    if (keep_attributes_) attributes = read_attributes(prim, positions.size(), where);
    glm::dmat4 world = node_world;
    if (node >= 0) {
        apply_morph_targets(prim, mesh_index, node, where, positions, normals, attributes.tangents);
        if (model_.nodes[size_t(node)].skin >= 0) {
            apply_skin(prim, node, where, positions, normals, attributes.tangents);
            world = glm::dmat4(1.0);  // skinned vertices are in world space already (spec 3.7.3.3)
        }
    }
    std::vector<uint32_t> indices;
    if (prim.indices >= 0) {
        indices = gltf::read_indices(model_, prim.indices, "indices of " + where);
        for (uint32_t i : indices)
            if (i >= positions.size())
                throw SceneError("index " + std::to_string(i) + " is out of range for " +
                                 std::to_string(positions.size()) + " vertices (accessor " +
                                 std::to_string(prim.indices) + ", indices of " + where + ")");
    } else {
        indices.resize(positions.size());
        for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES) leftover_indices_ += indices.size() % 3;
    const uint32_t material = material_index(variant_material(prim), where);
    const uint32_t sets = gltf::texcoord_sets_read(scene_.materials[material], scene_.material_layers[material],
                                                   scene_.texture_slots);
    for (uint32_t set = 0; set < 2; ++set)
        if ((sets & (1u << set)) && (set == 0 ? attributes.texcoords0 : attributes.texcoords1).empty())
            throw SceneError("material " + std::to_string(material) + " reads TEXCOORD_" + std::to_string(set) +
                             ", which " + where + " does not have");
    const size_t new_triangles = mode == TINYGLTF_MODE_TRIANGLES ? indices.size() / 3 : indices.size();
    if (triangle_material_.size() + new_triangles > MAX_SCENE_TRIANGLES)
        throw SceneError("the flattened scene exceeds " + std::to_string(MAX_SCENE_TRIANGLES) +
                         " triangles (at " + where + ")");

    const std::vector<std::array<uint32_t, 3>> triangles = make_triangles(mode, indices);
    // Without TANGENT, a material that needs a tangent frame gets MikkTSpace's (glTF spec 3.7.2.1: clients SHOULD).
    std::vector<std::array<glm::vec4, 3>> generated;
    if (generate_tangents_ && keep_attributes_ && attributes.tangents.empty() && !normals.empty()) {
        const int set = tangent_texcoord_set(material);
        const std::vector<glm::vec4>& uvs = set == 1 ? attributes.texcoords1 : attributes.texcoords0;
        if (set >= 0 && !uvs.empty()) generated = gltf::generate_tangents(triangles, positions, normals, uvs);
    }

    // Normals transform with the inverse transpose; a mirroring transform flips the winding.
    const glm::dmat3 linear(world);
    const glm::dmat3 normal_from_object = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) < 0.0;
    for (size_t t = 0; t < triangles.size(); ++t) {
        std::array<uint32_t, 3> tri = triangles[t];
        if (mirrored) std::swap(tri[1], tri[2]);
        rotate_to_lowest_vertex(tri, positions);
        std::array<glm::dvec3, 3> p;
        for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(world * glm::dvec4(glm::dvec3(positions[tri[k]]), 1.0));
        if (!is_finite(p[0]) || !is_finite(p[1]) || !is_finite(p[2])) {
            ++dropped_nonfinite_;
            continue;
        }
        // Without area already in double: dropped before the bounds (and the render origin) see it.
        const glm::dvec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
        if (!(glm::dot(c, c) > 0.0)) {
            ++dropped_degenerate_;
            continue;
        }
        std::array<glm::vec3, 3> n{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
        bool has_normals = !normals.empty();
        for (int k = 0; k < 3 && has_normals; ++k) {
            const glm::dvec3 w = normal_from_object * glm::dvec3(normals[tri[k]]);
            const double length = glm::length(w);
            n[k] = glm::vec3(w / length);
            has_normals = length > 0.0 && std::isfinite(length) && is_finite(n[k]);
        }
        if (!has_normals && !normals.empty()) ++flat_nonfinite_normals_;
        if (!has_normals) n = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
        world_positions_.insert(world_positions_.end(), p.begin(), p.end());
        normals_.insert(normals_.end(), n.begin(), n.end());
        if (keep_attributes_)
            add_triangle_attributes(attributes, tri, linear, mirrored,
                                    generated.empty() ? nullptr : &generated[t], triangles[t]);
        triangle_material_.push_back(material);
        triangle_has_normals_.push_back(has_normals ? 1 : 0);
    }
}

// Morph targets (spec 3.7.2.2): each target's POSITION, NORMAL and TANGENT displacements times its weight, the
// node's weights or else the mesh's (or an animation's, posed into the node before flattening).
void Flattener::apply_morph_targets(const tinygltf::Primitive& prim, int mesh_index, int node, const std::string& where,
                                    std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
                                    std::vector<glm::vec4>& tangents) {
    if (prim.targets.empty()) return;
    const std::vector<double>& node_weights = model_.nodes[size_t(node)].weights;
    const std::vector<double>& weights = !node_weights.empty() ? node_weights : model_.meshes[size_t(mesh_index)].weights;
    for (size_t t = 0; t < prim.targets.size() && t < weights.size(); ++t) {
        const float w = float(weights[t]);
        if (w == 0.0f) continue;
        if (!std::isfinite(w)) throw SceneError("morph weight " + std::to_string(t) + " is not finite (" + where + ")");
        auto displace = [&](const char* name, auto& values) {
            const auto it = prim.targets[t].find(name);
            if (it == prim.targets[t].end() || values.empty()) return;
            const std::string role = std::string(name) + " of morph target " + std::to_string(t) + " of " + where;
            const std::vector<glm::vec4> delta = gltf::read_vectors(model_, it->second, role, 3, 3, true);
            if (delta.size() != values.size())
                throw SceneError(role + " has " + std::to_string(delta.size()) + " elements, the primitive " +
                                 std::to_string(values.size()));
            for (size_t i = 0; i < values.size(); ++i)
                for (int c = 0; c < 3; ++c) values[i][c] += w * delta[i][c];
        };
        displace("POSITION", positions);
        displace("NORMAL", normals);
        displace("TANGENT", tangents);
    }
}

// Skinning (spec 3.7.3): each vertex placed by the weighted sum of its joints' world transforms times their
// inverse bind matrices; normals by the inverse transpose of that sum, tangents by the sum itself. The joints'
// world transforms come from the posed hierarchy (node_world_). Vertices whose weights sum to 0 stay with the node.
void Flattener::apply_skin(const tinygltf::Primitive& prim, int node, const std::string& where,
                           std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
                           std::vector<glm::vec4>& tangents) {
    const int skin_index = model_.nodes[size_t(node)].skin;
    if (size_t(skin_index) >= model_.skins.size())
        throw SceneError(describe_node(model_, node) + " has skin " + std::to_string(skin_index) + ", which does not exist");
    const tinygltf::Skin& skin = model_.skins[size_t(skin_index)];
    std::vector<glm::dmat4> joint_matrices(skin.joints.size(), glm::dmat4(1.0));
    std::vector<glm::dmat4> inverse_bind;
    if (skin.inverseBindMatrices >= 0) {
        inverse_bind = gltf::read_matrices(model_, skin.inverseBindMatrices, "inverseBindMatrices of skin " +
                                                                               std::to_string(skin_index));
        if (inverse_bind.size() < skin.joints.size())
            throw SceneError("skin " + std::to_string(skin_index) + " has " + std::to_string(skin.joints.size()) +
                             " joints but " + std::to_string(inverse_bind.size()) + " inverse bind matrices");
    }
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const int joint = skin.joints[j];
        if (joint < 0 || size_t(joint) >= model_.nodes.size())
            throw SceneError("skin " + std::to_string(skin_index) + " joint " + std::to_string(j) + " does not exist");
        joint_matrices[j] = node_world_[size_t(joint)] * (inverse_bind.empty() ? glm::dmat4(1.0) : inverse_bind[j]);
    }
    const glm::dmat4 node_world = node_world_[size_t(node)];
    std::vector<glm::vec4> joints, weights;
    for (int set = 0;; ++set) {
        const auto j = prim.attributes.find("JOINTS_" + std::to_string(set));
        const auto w = prim.attributes.find("WEIGHTS_" + std::to_string(set));
        if (j == prim.attributes.end() || w == prim.attributes.end()) break;
        const std::vector<glm::vec4> js = gltf::read_vectors(model_, j->second, j->first + " of " + where, 4, 4, true);
        const std::vector<glm::vec4> ws = gltf::read_vectors(model_, w->second, w->first + " of " + where, 4, 4, true);
        if (js.size() != positions.size() || ws.size() != positions.size())
            throw SceneError(j->first + " or " + w->first + " does not have one element per vertex (" + where + ")");
        joints.insert(joints.end(), js.begin(), js.end());
        weights.insert(weights.end(), ws.begin(), ws.end());
    }
    const size_t sets = positions.empty() ? 0 : joints.size() / positions.size();
    for (size_t i = 0; i < positions.size(); ++i) {
        glm::dmat4 m(0.0);
        double total = 0.0;
        for (size_t set = 0; set < sets; ++set)
            for (int k = 0; k < 4; ++k) {
                const double w = weights[set * positions.size() + i][k];
                if (w == 0.0) continue;
                const float joint_value = joints[set * positions.size() + i][k];
                if (!(joint_value >= 0.0f && joint_value < float(joint_matrices.size())))
                    throw SceneError("vertex " + std::to_string(i) + " names joint " + std::to_string(joint_value) +
                                     " of " + std::to_string(joint_matrices.size()) + " (" + where + ")");
                const size_t joint = size_t(joint_value);
                m += w * joint_matrices[joint];
                total += w;
            }
        m = total > 0.0 ? m / total : node_world;  // weights should sum to 1; renormalised where they do not
        positions[i] = glm::vec3(glm::dvec3(m * glm::dvec4(glm::dvec3(positions[i]), 1.0)));
        const glm::dmat3 linear(m);
        if (!normals.empty()) normals[i] = glm::vec3(glm::transpose(glm::inverse(linear)) * glm::dvec3(normals[i]));
        if (!tangents.empty()) tangents[i] = glm::vec4(glm::vec3(linear * glm::dvec3(tangents[i])), tangents[i].w);
    }
}

// Starts the triangle at its lexicographically lowest vertex, keeping the winding: encoders (meshopt's index
// codec, Draco) rotate triangles, and the image must not depend on which vertex a file lists first.
void Flattener::rotate_to_lowest_vertex(std::array<uint32_t, 3>& tri, const std::vector<glm::vec3>& positions) {
    auto lower = [&](uint32_t a, uint32_t b) {
        const glm::vec3 &p = positions[a], &q = positions[b];
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    size_t first = 0;
    for (size_t k = 1; k < 3; ++k)
        if (lower(tri[k], tri[first])) first = k;
    std::rotate(tri.begin(), tri.begin() + ptrdiff_t(first), tri.end());
}

// The material of `prim` in the chosen KHR_materials_variants variant: its mapping's, else its own.
int Flattener::variant_material(const tinygltf::Primitive& prim) const {
    if (variant_ < 0) return prim.material;
    const auto it = prim.extensions.find("KHR_materials_variants");
    if (it == prim.extensions.end() || !it->second.IsObject() || !it->second.Has("mappings")) return prim.material;
    const tinygltf::Value& mappings = it->second.Get("mappings");
    for (size_t m = 0; mappings.IsArray() && m < mappings.ArrayLen(); ++m) {
        const tinygltf::Value& mapping = mappings.Get(int(m));
        const tinygltf::Value& variants = gltf::json_member(mapping, "variants");
        for (size_t v = 0; variants.IsArray() && v < variants.ArrayLen(); ++v)
            if (variants.Get(int(v)).IsNumber() && gltf::read_json_index(variants.Get(int(v))) == variant_ &&
                gltf::json_member(mapping, "material").IsNumber())
                return gltf::read_json_index(gltf::json_member(mapping, "material"));
    }
    return prim.material;
}

// POSITION or NORMAL: float, or with KHR_mesh_quantization (normalized) byte and short components.
std::vector<glm::vec3> Flattener::read_vec3(int accessor, const std::string& role) {
    if (!quantized_) return gltf::read_float3(model_, accessor, role);
    const std::vector<glm::vec4> v = gltf::read_vectors(model_, accessor, role, 3, 3, true);
    std::vector<glm::vec3> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) out[i] = glm::vec3(v[i]);
    return out;
}

Flattener::VertexAttributes Flattener::read_attributes(const tinygltf::Primitive& prim, size_t vertex_count,
                                                       const std::string& where) {
    VertexAttributes a;
    auto read = [&](const char* name, int min_components, int max_components, std::vector<glm::vec4>& out) {
        const auto it = prim.attributes.find(name);
        if (it == prim.attributes.end()) return;
        const std::string role = std::string(name) + " of " + where;
        out = gltf::read_vectors(model_, it->second, role, min_components, max_components, true);
        if (out.size() != vertex_count)
            throw SceneError(std::string(name) + " has " + std::to_string(out.size()) + " elements but POSITION has " +
                             std::to_string(vertex_count) + " (accessor " + std::to_string(it->second) + ", " +
                             where + ")");
        for (const glm::vec4& v : out)
            if (!std::isfinite(v.x + v.y + v.z + v.w))
                throw SceneError(std::string(name) + " holds a NaN or infinite value (accessor " +
                                 std::to_string(it->second) + ", " + where + ")");
    };
    read("TEXCOORD_0", 2, 2, a.texcoords0);
    read("TEXCOORD_1", 2, 2, a.texcoords1);
    read("COLOR_0", 3, 4, a.colors);
    read("TANGENT", 4, 4, a.tangents);
    for (const glm::vec4& t : a.tangents)
        if (t.w != 1.0f && t.w != -1.0f)
            throw SceneError("TANGENT w must be 1 or -1 (the bitangent's sign), found " + std::to_string(t.w) +
                             " (" + where + ")");
    return a;
}

void Flattener::add_triangle_attributes(const VertexAttributes& a, const std::array<uint32_t, 3>& tri,
                                        const glm::dmat3& linear, bool mirrored,
                                        const std::array<glm::vec4, 3>* generated,
                                        const std::array<uint32_t, 3>& generated_order) {
    for (uint32_t v : tri) {
        texcoords0_.push_back(a.texcoords0.empty() ? glm::vec2(0.0f) : glm::vec2(a.texcoords0[v]));
        texcoords1_.push_back(a.texcoords1.empty() ? glm::vec2(0.0f) : glm::vec2(a.texcoords1[v]));
        colors_.push_back(a.colors.empty() ? glm::vec4(1.0f) : glm::clamp(a.colors[v], 0.0f, 1.0f));
        glm::vec4 object_tangent(0.0f);
        if (!a.tangents.empty()) object_tangent = a.tangents[v];
        else if (generated != nullptr)  // per corner, in the order make_triangles gave (before mirroring and rotation)
            for (int k = 0; k < 3; ++k)
                if (generated_order[size_t(k)] == v) object_tangent = (*generated)[size_t(k)];
        glm::vec4 tangent(0.0f);
        if (object_tangent.w != 0.0f) {
            // Tangents follow the surface (the linear part, not its inverse transpose); a mirroring transform
            // flips the handedness of the frame, so the bitangent sign flips with it.
            const glm::dvec3 t = linear * glm::dvec3(object_tangent);
            const double length = glm::length(t);
            if (length > 0.0 && std::isfinite(length))
                tangent = glm::vec4(glm::vec3(t / length), mirrored ? -object_tangent.w : object_tangent.w);
        }
        tangents_.push_back(tangent);
    }
}

int Flattener::tangent_texcoord_set(uint32_t material) const {
    const gpu::Material& m = scene_.materials[material];
    const gpu::MaterialLayers& layers = scene_.material_layers[material];
    for (uint32_t slot : {m.normal_texture, layers.clearcoat_normal_texture, layers.anisotropy_texture})
        if (slot != gpu::INVALID_INDEX && slot < scene_.texture_slots.size())
            return (scene_.texture_slots[slot].addressing & gpu::SAMPLER_TEXCOORD_1) ? 1 : 0;
    return layers.anisotropy_strength > 0.0f ? 0 : -1;
}

}  // namespace fh::gltf
