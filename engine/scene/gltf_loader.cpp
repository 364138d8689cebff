// load_gltf: walks the node hierarchy of a glTF 2.0 file and flattens every triangle into world space.
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_accessor.h"
#include "scene/gltf_material.h"
#include "scene/scene.h"

namespace fh {
namespace {

constexpr int MAX_NODE_DEPTH = 1024;  // deeper hierarchies are treated as malformed
// A node with several parents is drawn once per path from the root (instancing; glTF itself requires the
// nodes to form disjoint trees). Sharing can multiply: 40 nodes that each list the next twice make 2^40
// paths, so the walk stops at this many node instances, and the flattened scene at this many triangles
// (about 5 GB on the host; the device limits in render/memory_estimate.h are usually far lower).
constexpr size_t MAX_NODE_INSTANCES = size_t(1) << 22;
constexpr size_t MAX_SCENE_TRIANGLES = size_t(1) << 26;

// Textures are not read yet: skip decoding images (tinygltf would otherwise decode every one).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
    return true;
}

// tinygltf messages span several lines; errors must fit on one.
std::string join_lines(const std::string& text, const char* separator) {
    std::string out;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (line.empty()) continue;
        if (!out.empty()) out += separator;
        out += line;
    }
    return out;
}

bool has_glb_magic(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    return in.gcount() == 4 && std::string(magic, 4) == "glTF";
}

tinygltf::Model read_model(const std::filesystem::path& file, std::vector<std::string>& warnings) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) throw SceneError("file not found");
    tinygltf::TinyGLTF parser;
    parser.SetImageLoader(&skip_image, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = has_glb_magic(file) ? parser.LoadBinaryFromFile(&model, &err, &warn, file.string())
                                        : parser.LoadASCIIFromFile(&model, &err, &warn, file.string());
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) warnings.push_back("tinygltf: " + line);
    if (!ok || !err.empty()) {
        const std::string message = join_lines(err, "; ");
        throw SceneError("tinygltf: " + (message.empty() ? std::string("could not parse the file") : message));
    }
    return model;
}

void check_extensions(const tinygltf::Model& model, std::vector<std::string>& warnings) {
    for (const std::string& name : model.extensionsRequired)
        if (!gltf::is_supported_extension(name))
            throw SceneError("required extension " + name + " is not supported (extensionsRequired)");
    for (const std::string& name : model.extensionsUsed)
        if (!gltf::is_supported_extension(name))
            warnings.push_back("extension " + name + " is not supported and is ignored");
    if (!model.textures.empty()) warnings.push_back("textures are not supported yet: material factors only");
}

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

bool is_finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Flattens the nodes of one scene into `scene`.
class Flattener {
public:
    Flattener(const tinygltf::Model& model, Scene& scene)
        : model_(model), scene_(scene), on_path_(model.nodes.size(), 0) {}

    void visit_node(int index, const glm::dmat4& parent_world, int depth) {
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
        // Transforms cannot be NaN in JSON, but scales and matrices can overflow when composed.
        if (!is_finite(world))
            throw SceneError("the world transform of " + describe_node(model_, index) +
                             " is not finite (its transform or an ancestor's overflows)");
        if (node.skin >= 0) warn_once("skins are not supported: skinned meshes are drawn in their bind pose");
        if (node.mesh >= 0) add_mesh(node.mesh, world);
        if (node.camera >= 0) add_camera(node.camera, index, world);
        for (int child : node.children) {
            if (child < 0 || size_t(child) >= model_.nodes.size())
                throw SceneError(describe_node(model_, index) + " has child " + std::to_string(child) +
                                 ", which does not exist");
            visit_node(child, world, depth + 1);
        }
        on_path_[size_t(index)] = 0;
    }

    void finish() {
        for (const auto& [mode, count] : skipped_modes_)
            scene_.warnings.push_back("skipped " + std::to_string(count) + " primitive(s) drawn as " + mode);
        if (dropped_nonfinite_ > 0)
            scene_.warnings.push_back("dropped " + std::to_string(dropped_nonfinite_) +
                                      " triangle(s) with NaN or infinite positions");
        if (flat_nonfinite_normals_ > 0)
            scene_.warnings.push_back("shaded " + std::to_string(flat_nonfinite_normals_) +
                                      " triangle(s) flat: NaN, infinite or zero normals");
        if (leftover_indices_ > 0)
            scene_.warnings.push_back("ignored " + std::to_string(leftover_indices_) +
                                      " trailing index(es) that do not complete a triangle");
    }

private:
    void warn_once(const std::string& message) {
        if (warned_.emplace(message, 1).second) scene_.warnings.push_back(message);
    }

    void add_mesh(int mesh_index, const glm::dmat4& world) {
        if (size_t(mesh_index) >= model_.meshes.size())
            throw SceneError("mesh " + std::to_string(mesh_index) + " does not exist");
        const tinygltf::Mesh& mesh = model_.meshes[size_t(mesh_index)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) add_primitive(mesh.primitives[p], mesh_index, int(p), world);
    }

    uint32_t material_index(int material, const std::string& where) {
        if (material >= 0) {
            if (size_t(material) >= model_.materials.size())
                throw SceneError("material " + std::to_string(material) + " does not exist (" + where + ")");
            return uint32_t(material);
        }
        if (default_material_ == gpu::INVALID_INDEX) {
            default_material_ = uint32_t(scene_.materials.size());
            scene_.materials.push_back(gltf::make_default_material());
        }
        return default_material_;
    }

    void add_primitive(const tinygltf::Primitive& prim, int mesh_index, int prim_index, const glm::dmat4& world) {
        const std::string where = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(prim_index);
        const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            ++skipped_modes_[mode_name(mode)];
            return;
        }
        if (!prim.targets.empty()) warn_once("morph targets are not supported: meshes are drawn unmorphed");
        const auto position_it = prim.attributes.find("POSITION");
        if (position_it == prim.attributes.end()) throw SceneError("primitive has no POSITION (" + where + ")");
        const std::vector<glm::vec3> positions = gltf::read_float3(model_, position_it->second, "POSITION of " + where);
        std::vector<glm::vec3> normals;
        if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
            normals = gltf::read_float3(model_, it->second, "NORMAL of " + where);
            if (normals.size() != positions.size())
                throw SceneError("NORMAL has " + std::to_string(normals.size()) + " elements but POSITION has " +
                                 std::to_string(positions.size()) + " (accessor " + std::to_string(it->second) +
                                 ", " + where + ")");
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
        const uint32_t material = material_index(prim.material, where);
        const size_t new_triangles = mode == TINYGLTF_MODE_TRIANGLES ? indices.size() / 3 : indices.size();
        if (scene_.triangle_count() + new_triangles > MAX_SCENE_TRIANGLES)
            throw SceneError("the flattened scene exceeds " + std::to_string(MAX_SCENE_TRIANGLES) +
                             " triangles (at " + where + ")");

        // Normals transform with the inverse transpose; a mirroring transform flips the winding.
        const glm::dmat3 linear(world);
        const glm::dmat3 normal_from_object = glm::transpose(glm::inverse(linear));
        const bool mirrored = glm::determinant(linear) < 0.0;
        for (std::array<uint32_t, 3> tri : make_triangles(mode, indices)) {
            if (mirrored) std::swap(tri[1], tri[2]);
            std::array<glm::vec3, 3> p;
            for (int k = 0; k < 3; ++k) p[k] = glm::vec3(world * glm::dvec4(glm::dvec3(positions[tri[k]]), 1.0));
            if (!is_finite(p[0]) || !is_finite(p[1]) || !is_finite(p[2])) {
                ++dropped_nonfinite_;
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
            scene_.positions.insert(scene_.positions.end(), p.begin(), p.end());
            scene_.normals.insert(scene_.normals.end(), n.begin(), n.end());
            scene_.triangle_material.push_back(material);
            scene_.triangle_has_normals.push_back(has_normals ? 1 : 0);
        }
    }

    void add_camera(int camera_index, int node_index, const glm::dmat4& world) {
        if (size_t(camera_index) >= model_.cameras.size())
            throw SceneError("camera " + std::to_string(camera_index) + " does not exist (" +
                             describe_node(model_, node_index) + ")");
        const tinygltf::Camera& source = model_.cameras[size_t(camera_index)];
        SceneCamera camera;
        camera.name = !source.name.empty() ? source.name : model_.nodes[size_t(node_index)].name;
        camera.world_from_camera = world;
        camera.orthographic = source.type == "orthographic";
        camera.yfov = source.perspective.yfov;
        camera.xmag = source.orthographic.xmag;
        camera.ymag = source.orthographic.ymag;
        scene_.cameras.push_back(camera);
    }

    const tinygltf::Model& model_;
    Scene& scene_;
    std::vector<uint8_t> on_path_;  // 1 while a node is an ancestor of the one being visited
    uint32_t default_material_ = gpu::INVALID_INDEX;
    std::map<std::string, size_t> skipped_modes_;
    std::map<std::string, int> warned_;
    size_t dropped_nonfinite_ = 0;
    size_t flat_nonfinite_normals_ = 0;
    size_t instances_ = 0;
    size_t leftover_indices_ = 0;
};

// The root nodes to draw: the default scene, else the first; without scenes, every node no one parents.
std::vector<int> find_root_nodes(const tinygltf::Model& model, std::vector<std::string>& warnings) {
    if (!model.scenes.empty()) {
        const int index = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (size_t(index) >= model.scenes.size())
            throw SceneError("default scene " + std::to_string(index) + " does not exist");
        return model.scenes[size_t(index)].nodes;
    }
    warnings.push_back("the file defines no scene: drawing every root node");
    std::vector<uint8_t> is_child(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < is_child.size()) is_child[size_t(child)] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < model.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(int(i));
    return roots;
}

// glTF nodes must form disjoint trees; a node listed as the child of several nodes is drawn once per parent.
void warn_about_shared_nodes(const tinygltf::Model& model, std::vector<std::string>& warnings) {
    std::vector<uint32_t> parents(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < parents.size()) ++parents[size_t(child)];
    size_t shared = 0;
    int first = -1;
    for (size_t i = 0; i < parents.size(); ++i)
        if (parents[i] > 1 && shared++ == 0) first = int(i);
    if (shared > 0)
        warnings.push_back(std::to_string(shared) + " node(s) have several parents (first: " +
                           describe_node(model, first) + "): drawn once per parent, although glTF requires a tree");
}

Scene load_unprefixed(const std::filesystem::path& file) {
    Scene scene;
    scene.source = file;
    const tinygltf::Model model = read_model(file, scene.warnings);
    check_extensions(model, scene.warnings);
    for (const tinygltf::Material& material : model.materials)
        scene.materials.push_back(gltf::convert_material(material));

    warn_about_shared_nodes(model, scene.warnings);
    Flattener flattener(model, scene);
    for (int root : find_root_nodes(model, scene.warnings)) flattener.visit_node(root, glm::dmat4(1.0), 0);
    flattener.finish();
    if (scene.triangle_count() == 0) throw SceneError("no triangles in the scene");

    scene.bounds_min = glm::dvec3(std::numeric_limits<double>::infinity());
    scene.bounds_max = -scene.bounds_min;
    for (const glm::vec3& p : scene.positions) {
        scene.bounds_min = glm::min(scene.bounds_min, glm::dvec3(p));
        scene.bounds_max = glm::max(scene.bounds_max, glm::dvec3(p));
    }
    return scene;
}

}  // namespace

Scene load_gltf(const std::filesystem::path& file) {
    try {
        return load_unprefixed(file);
    } catch (const SceneError& e) {
        throw SceneError(file.string() + ": " + e.what());
    } catch (const std::bad_alloc&) {
        throw SceneError(file.string() + ": out of memory while loading the scene");
    } catch (const std::exception& e) {  // from tinygltf or the standard library: still name the file
        throw SceneError(file.string() + ": " + e.what());
    }
}

}  // namespace fh
