// load_gltf: walks the node hierarchy of a glTF 2.0 file and flattens every triangle into world space.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <new>
#include <sstream>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_accessor.h"
#include "scene/gltf_material.h"
#include "scene/gltf_texture.h"
#include "scene/scene.h"

namespace fh {
namespace {

constexpr int MAX_NODE_DEPTH = 1024;  // deeper hierarchies are treated as malformed
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

// The .gltf, its .bin buffers and its images are read only if they are regular files of at most this size.
// A URI may name anything: a FIFO blocked tinygltf's fopen() forever (deaf to SIGTERM), a directory reports a
// size near 2^63 that tinygltf tried to allocate, a device is no data, and a huge file would be read whole.
constexpr uint64_t MAX_FILE_BYTES = uint64_t(2) << 30;

// tinygltf's FileExists opens the file, which blocks on a FIFO; stat() does not.
bool file_exists(const std::string& path, void*) {
    struct stat info;
    return ::stat(path.c_str(), &info) == 0;
}

// Reads a regular file whole; `err` gets the problem without the path (tinygltf prefixes it).
bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // O_NONBLOCK: a FIFO opens at once
    if (fd < 0) {
        *err += std::string("cannot open: ") + std::strerror(errno);
        return false;
    }
    struct stat info;
    std::string problem;
    if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
        problem = "not a regular file (a directory, device or pipe)";
    else if (uint64_t(info.st_size) > MAX_FILE_BYTES)
        problem = std::to_string(info.st_size) + " bytes, more than the limit of " + std::to_string(MAX_FILE_BYTES);
    else if (info.st_size == 0)
        problem = "File is empty";
    size_t done = 0;
    if (problem.empty()) {
        out->resize(size_t(info.st_size));
        while (done < out->size()) {
            const ssize_t n = ::read(fd, out->data() + done, out->size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) problem = std::string("read error: ") + std::strerror(errno);
            if (n <= 0) break;
            done += size_t(n);
        }
        out->resize(done);  // a file that shrank meanwhile: the size checks of the callers see the short read
    }
    ::close(fd);
    *err += problem;
    return problem.empty();
}

bool has_glb_magic(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    return in.gcount() == 4 && std::string(magic, 4) == "glTF";
}

uint64_t load_le32(const unsigned char* p) { return p[0] | p[1] << 8 | p[2] << 16 | uint64_t(p[3]) << 24; }

// tinygltf 2.7.0 checks a GLB's BIN chunk against the file length without the chunk's 8-byte header, then reads
// up to 8 bytes past the end of the file (a heap-buffer-overflow found by the fuzzer:
// tests/fuzz/regressions/crash_glb_bin_chunk_past_end.glb). The header layout is in glTF 2.0 spec section 4.4.
void check_glb_bin_chunk(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char header[20] = {}, chunk[4] = {};
    if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return;  // tinygltf reports a short file
    const uint64_t length = load_le32(header + 8), bin_at = 20 + load_le32(header + 12);
    std::error_code ec;
    if (length > std::filesystem::file_size(file, ec) || ec || bin_at + 12 > length) return;  // tinygltf's cases
    if (!in.seekg(std::streamoff(bin_at)) || !in.read(reinterpret_cast<char*>(chunk), sizeof chunk)) return;
    if (bin_at + 8 + load_le32(chunk) > length)
        throw SceneError("invalid GLB: the BIN chunk (" + std::to_string(load_le32(chunk)) + " bytes from byte " +
                         std::to_string(bin_at + 8) + ") ends past the " + std::to_string(length) +
                         "-byte file");
}

tinygltf::Model read_model(const std::filesystem::path& file, std::vector<std::string>& warnings) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) throw SceneError("file not found");
    tinygltf::TinyGLTF parser;
    parser.SetImageLoader(&gltf::load_image_data, nullptr);
    parser.SetFsCallbacks(
        {&file_exists, &tinygltf::ExpandFilePath, &read_regular_file, &tinygltf::WriteWholeFile, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const bool is_glb = has_glb_magic(file);
    if (is_glb) check_glb_bin_chunk(file);
    const bool ok = is_glb ? parser.LoadBinaryFromFile(&model, &err, &warn, file.string())
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
bool is_finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Flattens the nodes of one scene into `scene`.
class Flattener {
public:
    Flattener(const tinygltf::Model& model, Scene& scene, int variant)
        : model_(model), scene_(scene), on_path_(model.nodes.size(), 0), variant_(variant) {
        keep_attributes_ = !model.textures.empty();
        for (const std::string& name : model.extensionsUsed) quantized_ = quantized_ || name == "KHR_mesh_quantization";
        for (const tinygltf::Mesh& mesh : model.meshes)
            for (const tinygltf::Primitive& prim : mesh.primitives)
                keep_attributes_ = keep_attributes_ || prim.attributes.count("COLOR_0") != 0;
    }

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
        if (const auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end())
            add_light(it->second, index, world);
        for (int child : node.children) {
            if (child < 0 || size_t(child) >= model_.nodes.size())
                throw SceneError(describe_node(model_, index) + " has child " + std::to_string(child) +
                                 ", which does not exist");
            visit_node(child, world, depth + 1);
        }
        on_path_[size_t(index)] = 0;
    }

    // Places the triangles in render space (LoadOptions::rebase) and drops those without area there.
    void finish(bool rebase) {
        glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        for (const glm::dvec3& p : world_positions_) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        if (!world_positions_.empty()) {
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

private:
    // Rounds world positions (double) minus `origin` to float, keeping the triangles whose float cross
    // product is not zero: the GPU could neither hit them (zero determinant) nor give them a normal.
    void place_triangles(const glm::dvec3& origin) {
        for (size_t t = 0; t < triangle_material_.size(); ++t) {
            std::array<glm::vec3, 3> p;
            for (int k = 0; k < 3; ++k) p[size_t(k)] = glm::vec3(world_positions_[3 * t + size_t(k)] - origin);
            const glm::vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
            if (!(glm::dot(c, c) > 0.0f) || !is_finite(c)) {
                ++dropped_degenerate_;
                continue;
            }
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
        world_positions_.clear();
        world_positions_.shrink_to_fit();
        for (SceneLight& light : scene_.lights) light.position -= origin;
    }

    void warn_once(const std::string& message) {
        if (warned_.emplace(message, 1).second) scene_.warnings.push_back(message);
    }

    void add_mesh(int mesh_index, const glm::dmat4& world) {
        if (size_t(mesh_index) >= model_.meshes.size())
            throw SceneError("mesh " + std::to_string(mesh_index) + " does not exist");
        const tinygltf::Mesh& mesh = model_.meshes[size_t(mesh_index)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            const size_t before = triangle_material_.size();
            add_primitive(prim, mesh_index, int(p), world);
            // Unique triangles: a primitive's geometry (its POSITION and index accessors and mode) counted at its
            // first use, however many nodes or meshes draw it (before degenerate ones are dropped).
            const auto position = prim.attributes.find("POSITION");
            const std::array<int, 3> key{position == prim.attributes.end() ? -1 : position->second, prim.indices, prim.mode};
            if (geometry_seen_.insert(key).second) scene_.unique_triangle_count += triangle_material_.size() - before;
        }
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
        const std::vector<glm::vec3> positions = read_vec3(position_it->second, "POSITION of " + where);
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
        const uint32_t sets = gltf::texcoord_sets_read(scene_.materials[material], scene_.texture_slots);
        for (uint32_t set = 0; set < 2; ++set)
            if ((sets & (1u << set)) && (set == 0 ? attributes.texcoords0 : attributes.texcoords1).empty())
                throw SceneError("material " + std::to_string(material) + " reads TEXCOORD_" + std::to_string(set) +
                                 ", which " + where + " does not have");
        const size_t new_triangles = mode == TINYGLTF_MODE_TRIANGLES ? indices.size() / 3 : indices.size();
        if (triangle_material_.size() + new_triangles > MAX_SCENE_TRIANGLES)
            throw SceneError("the flattened scene exceeds " + std::to_string(MAX_SCENE_TRIANGLES) +
                             " triangles (at " + where + ")");

        // Normals transform with the inverse transpose; a mirroring transform flips the winding.
        const glm::dmat3 linear(world);
        const glm::dmat3 normal_from_object = glm::transpose(glm::inverse(linear));
        const bool mirrored = glm::determinant(linear) < 0.0;
        for (std::array<uint32_t, 3> tri : make_triangles(mode, indices)) {
            if (mirrored) std::swap(tri[1], tri[2]);
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
            if (keep_attributes_) add_triangle_attributes(attributes, tri, linear, mirrored);
            triangle_material_.push_back(material);
            triangle_has_normals_.push_back(has_normals ? 1 : 0);
        }
    }

    // The material of `prim` in the chosen KHR_materials_variants variant: its mapping's, else its own.
    int variant_material(const tinygltf::Primitive& prim) const {
        if (variant_ < 0) return prim.material;
        const auto it = prim.extensions.find("KHR_materials_variants");
        if (it == prim.extensions.end() || !it->second.IsObject() || !it->second.Has("mappings")) return prim.material;
        const tinygltf::Value& mappings = it->second.Get("mappings");
        for (size_t m = 0; mappings.IsArray() && m < mappings.ArrayLen(); ++m) {
            const tinygltf::Value& mapping = mappings.Get(int(m));
            const tinygltf::Value& variants = mapping.Get("variants");
            for (size_t v = 0; variants.IsArray() && v < variants.ArrayLen(); ++v)
                if (variants.Get(int(v)).IsNumber() && variants.Get(int(v)).GetNumberAsInt() == variant_ &&
                    mapping.Get("material").IsNumber())
                    return mapping.Get("material").GetNumberAsInt();
        }
        return prim.material;
    }

    // POSITION or NORMAL: float, or with KHR_mesh_quantization (normalized) byte and short components.
    std::vector<glm::vec3> read_vec3(int accessor, const std::string& role) {
        if (!quantized_) return gltf::read_float3(model_, accessor, role);
        const std::vector<glm::vec4> v = gltf::read_vectors(model_, accessor, role, 3, 3, true);
        std::vector<glm::vec3> out(v.size());
        for (size_t i = 0; i < v.size(); ++i) out[i] = glm::vec3(v[i]);
        return out;
    }

    // The attributes of one primitive's vertices that textures and vertex colours read (empty if absent).
    struct VertexAttributes {
        std::vector<glm::vec4> texcoords0, texcoords1, colors, tangents;
    };

    VertexAttributes read_attributes(const tinygltf::Primitive& prim, size_t vertex_count, const std::string& where) {
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

    void add_triangle_attributes(const VertexAttributes& a, const std::array<uint32_t, 3>& tri, const glm::dmat3& linear,
                                 bool mirrored) {
        for (uint32_t v : tri) {
            texcoords0_.push_back(a.texcoords0.empty() ? glm::vec2(0.0f) : glm::vec2(a.texcoords0[v]));
            texcoords1_.push_back(a.texcoords1.empty() ? glm::vec2(0.0f) : glm::vec2(a.texcoords1[v]));
            colors_.push_back(a.colors.empty() ? glm::vec4(1.0f) : glm::clamp(a.colors[v], 0.0f, 1.0f));
            glm::vec4 tangent(0.0f);
            if (!a.tangents.empty()) {
                // Tangents follow the surface (the linear part, not its inverse transpose); a mirroring transform
                // flips the handedness of the frame, so the bitangent sign flips with it.
                const glm::dvec3 t = linear * glm::dvec3(a.tangents[v]);
                const double length = glm::length(t);
                if (length > 0.0 && std::isfinite(length))
                    tangent = glm::vec4(glm::vec3(t / length), mirrored ? -a.tangents[v].w : a.tangents[v].w);
            }
            tangents_.push_back(tangent);
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

    // A KHR_lights_punctual reference on a node: {"light": index}.
    void add_light(const tinygltf::Value& extension, int node_index, const glm::dmat4& world) {
        const tinygltf::Value& index_value = extension.Get("light");
        if (!index_value.IsInt() && !index_value.IsNumber())
            throw SceneError(describe_node(model_, node_index) + ": KHR_lights_punctual has no light index");
        const double index = index_value.IsInt() ? double(index_value.Get<int>()) : index_value.Get<double>();
        if (!(index >= 0.0 && index < double(model_.lights.size())) || index != std::floor(index))
            throw SceneError(describe_node(model_, node_index) + ": KHR_lights_punctual light " +
                             (index == std::floor(index) && std::abs(index) < 1e15 ? std::to_string((long long)index)
                                                                                 : std::to_string(index)) +
                             " does not exist (" + std::to_string(model_.lights.size()) +
                             " lights)");
        const tinygltf::Light& source = model_.lights[size_t(index)];
        const std::string where = "light " + std::to_string(size_t(index)) + " on " + describe_node(model_, node_index);
        SceneLight light;
        light.name = source.name;
        if (source.type == "point") light.type = gpu::LIGHT_POINT;
        else if (source.type == "spot") light.type = gpu::LIGHT_SPOT;
        else if (source.type == "directional") light.type = gpu::LIGHT_DIRECTIONAL;
        else throw SceneError(where + " has unknown type '" + source.type + "'");
        glm::dvec3 color(1.0);
        if (source.color.size() == 3) color = glm::dvec3(source.color[0], source.color[1], source.color[2]);
        const glm::dvec3 intensity = color * source.intensity;
        if (!(intensity.x >= 0.0 && intensity.y >= 0.0 && intensity.z >= 0.0) ||
            !std::isfinite(intensity.x + intensity.y + intensity.z) || std::max({intensity.x, intensity.y, intensity.z}) > 3.0e38)
            throw SceneError(where + " has a negative or non-finite color * intensity");
        light.intensity = glm::vec3(intensity);
        light.position = glm::dvec3(world[3]);
        const glm::dvec3 axis = -glm::dvec3(world[2]);  // the node's local -Z
        const double length = glm::length(axis);
        if (!(length > 0.0) || !std::isfinite(length))
            throw SceneError(where + ": the node's transform has no direction (zero or non-finite -Z axis)");
        light.direction = axis / length;
        if (light.type == gpu::LIGHT_SPOT) {
            light.inner_cone = float(source.spot.innerConeAngle);
            light.outer_cone = float(source.spot.outerConeAngle);
            if (!(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone &&
                  light.outer_cone <= 0.5f * glm::pi<float>()))
                throw SceneError(where + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
        }
        if (source.range > 0.0) warn_once("KHR_lights_punctual range is ignored (lights follow the inverse-square law)");
        scene_.lights.push_back(light);
    }

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
    // Finite trees always have a root; without one, "no triangles" would hide the real problem.
    if (roots.empty() && !model.nodes.empty())
        throw SceneError("every node is the child of another: the node hierarchy is a cycle "
                         "(and no scene lists roots)");
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

// The walk visits a node once per path from a root, so shared children multiply: a 600-byte file of 40 nodes
// that each list the next twice took seconds to reach MAX_NODE_INSTANCES (a fuzzer timeout under ASan).
// Counting paths in topological order (Kahn) costs O(nodes + children) and refuses such files at once. Nodes on
// or below a cycle are not counted: the walk reports the cycle, or stops at the limit itself.
void check_node_instances(const tinygltf::Model& model, const std::vector<int>& roots) {
    const size_t n = model.nodes.size();
    std::vector<size_t> parents(n, 0), paths(n, 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < n) ++parents[size_t(child)];
    for (int root : roots)
        if (root >= 0 && size_t(root) < n) ++paths[size_t(root)];
    std::vector<size_t> ready;
    for (size_t i = 0; i < n; ++i)
        if (parents[i] == 0) ready.push_back(i);
    size_t instances = 0;
    while (!ready.empty()) {
        const size_t i = ready.back();
        ready.pop_back();
        instances += paths[i];  // each term is at most MAX_NODE_INSTANCES: no overflow before the check
        if (instances > MAX_NODE_INSTANCES)
            throw SceneError("the node hierarchy has more than " + std::to_string(MAX_NODE_INSTANCES) +
                             " node instances (nodes shared by several parents multiply; at " +
                             describe_node(model, int(i)) + ")");
        for (int child : model.nodes[i].children) {
            if (child < 0 || size_t(child) >= n) continue;
            paths[size_t(child)] = std::min(paths[size_t(child)] + paths[i], MAX_NODE_INSTANCES + 1);
            if (--parents[size_t(child)] == 0) ready.push_back(size_t(child));
        }
    }
}

// KHR_materials_variants: the names the file defines, and the index of `wanted` among them (-1 for "").
int choose_variant(const tinygltf::Model& model, const std::string& wanted, std::vector<std::string>& names) {
    const auto it = model.extensions.find("KHR_materials_variants");
    if (it != model.extensions.end() && it->second.IsObject() && it->second.Has("variants")) {
        const tinygltf::Value& variants = it->second.Get("variants");
        for (size_t v = 0; variants.IsArray() && v < variants.ArrayLen(); ++v) {
            const tinygltf::Value& name = variants.Get(int(v)).Get("name");
            names.push_back(name.IsString() ? name.Get<std::string>() : "variant " + std::to_string(v));
        }
    }
    if (wanted.empty()) return -1;
    for (size_t v = 0; v < names.size(); ++v)
        if (names[v] == wanted) return int(v);
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + ("'" + n + "'");
    throw SceneError("no material variant '" + wanted + "' (KHR_materials_variants; the file has " +
                     (known.empty() ? std::string("none") : known) + ")");
}

Scene load_unprefixed(const std::filesystem::path& file, const LoadOptions& options) {
    Scene scene;
    scene.source = file;
    tinygltf::Model model = read_model(file, scene.warnings);
    check_extensions(model, scene.warnings);
    scene.images = gltf::take_images(model);
    for (size_t m = 0; m < model.materials.size(); ++m)
        scene.materials.push_back(gltf::convert_material(model, int(m), scene));

    warn_about_shared_nodes(model, scene.warnings);
    Flattener flattener(model, scene, choose_variant(model, options.variant, scene.variants));
    const std::vector<int> roots = find_root_nodes(model, scene.warnings);
    check_node_instances(model, roots);
    for (int root : roots) flattener.visit_node(root, glm::dmat4(1.0), 0);
    flattener.finish(options.rebase);
    if (scene.triangle_count() == 0) throw SceneError("no triangles in the scene");
    return scene;
}

}  // namespace

Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options) {
    try {
        return load_unprefixed(file, options);
    } catch (const SceneError& e) {
        throw SceneError(file.string() + ": " + e.what());
    } catch (const std::bad_alloc&) {
        throw SceneError(file.string() + ": out of memory while loading the scene");
    } catch (const std::exception& e) {  // from tinygltf or the standard library: still name the file
        throw SceneError(file.string() + ": " + e.what());
    }
}

}  // namespace fh
