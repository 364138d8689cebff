// load_gltf: walks the node hierarchy of a glTF 2.0 file and flattens every triangle into world space.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
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
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_material.h"
#include "scene/thin_film_bound.h"
#include "scene/gltf_draco.h"
#include "scene/gltf_meshopt.h"
#include "scene/gltf_texture.h"
#include "scene/json_limits.h"
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

// `json` patched where tinygltf would refuse what a compression extension allows (gltf_meshopt.h,
// gltf_draco.h); false when nothing needed it.
bool patch_for_decoders(std::string& json, std::vector<gltf::FallbackBuffer>& fallbacks) {
    if (json.find("EXT_meshopt_compression") == std::string::npos &&
        json.find("KHR_draco_mesh_compression") == std::string::npos)
        return false;
    nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_discarded()) return false;  // tinygltf reports bad JSON
    const bool meshopt = gltf::patch_meshopt_fallbacks(doc, fallbacks, MAX_FILE_BYTES);
    const bool draco = gltf::patch_draco_indices(doc);
    if (!meshopt && !draco) return false;
    json = doc.dump();
    return true;
}

// The file's JSON text: the whole .gltf, or a .glb's JSON chunk (`json_end`: the byte after it). Empty when the
// file cannot be read so (tinygltf then reads the file itself and reports the problem).
std::string read_json_text(const std::filesystem::path& file, bool is_glb, uint64_t& json_end) {
    std::string json;
    json_end = 0;
    if (!is_glb) {
        std::vector<unsigned char> bytes;
        std::string problem;
        if (!read_regular_file(&bytes, &problem, file.string(), nullptr)) return {};
        return std::string(bytes.begin(), bytes.end());
    }
    std::ifstream in(file, std::ios::binary);
    unsigned char header[20] = {};
    if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return {};
    const uint64_t json_length = load_le32(header + 12);
    std::error_code ec;
    if (20 + json_length > std::filesystem::file_size(file, ec) || ec || json_length > MAX_FILE_BYTES) return {};
    json.resize(size_t(json_length));
    if (!in.read(json.data(), std::streamsize(json_length))) return {};
    json_end = 20 + json_length;
    return json;
}

// The file's JSON (`json`, as read_json_text gave it) patched for the compression extensions (patch_for_decoders),
// as a .gltf text or a rebuilt .glb; empty when the file does not need it (tinygltf then reads the file itself).
std::vector<unsigned char> patch_file_for_decoders(const std::filesystem::path& file, bool is_glb,
                                                   const std::string& text, uint64_t json_end,
                                                   std::vector<gltf::FallbackBuffer>& fallbacks) {
    if (text.empty()) return {};
    std::string json = text;
    if (!patch_for_decoders(json, fallbacks)) return {};
    if (!is_glb) return std::vector<unsigned char>(json.begin(), json.end());
    std::vector<unsigned char> bytes;
    std::string problem;
    if (!read_regular_file(&bytes, &problem, file.string(), nullptr) || bytes.size() < json_end) return {};
    // Only the bytes the header's length covers, and only when it covers the JSON and no more than the file
    // (else tinygltf reads the file itself and reports it): check_glb_bin_chunk judged the chunks against
    // that length, and a rebuilt header must not grant a BIN chunk more than it did (a fuzzer finding,
    // tests/fuzz/regressions/crash_meshopt_glb_length.glb).
    const uint64_t length = load_le32(bytes.data() + 8);
    if (length > bytes.size() || length < json_end) return {};
    while (json.size() % 4 != 0) json += ' ';
    std::vector<unsigned char> glb(bytes.begin(), bytes.begin() + 12);
    auto put32 = [&](uint64_t v) {
        for (int i = 0; i < 4; ++i) glb.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    put32(json.size());
    put32(0x4E4F534Au);  // "JSON"
    glb.insert(glb.end(), json.begin(), json.end());
    glb.insert(glb.end(), bytes.begin() + ptrdiff_t(json_end), bytes.begin() + ptrdiff_t(length));
    const uint64_t total = glb.size();
    for (int i = 0; i < 4; ++i) glb[size_t(8 + i)] = static_cast<unsigned char>(total >> (8 * i));
    return glb;
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
    // Nesting is checked before any recursive parse: tinygltf's parse and destruction recurse per level.
    uint64_t json_end = 0;
    std::string json = read_json_text(file, is_glb, json_end);
    check_json_nesting(json, is_glb ? "the GLB's JSON chunk" : "the JSON");
    std::vector<gltf::FallbackBuffer> fallbacks;
    const std::vector<unsigned char> patched = patch_file_for_decoders(file, is_glb, json, json_end, fallbacks);
    const std::string base_dir = file.parent_path().string();
    bool ok;
    if (patched.empty() && !is_glb && !json.empty())  // the text read above, not the file read again
        ok = parser.LoadASCIIFromString(&model, &err, &warn, json.data(), unsigned(json.size()), base_dir);
    else if (patched.empty())
        ok = is_glb ? parser.LoadBinaryFromFile(&model, &err, &warn, file.string())
                    : parser.LoadASCIIFromFile(&model, &err, &warn, file.string());
    else
        ok = is_glb ? parser.LoadBinaryFromMemory(&model, &err, &warn, patched.data(), unsigned(patched.size()), base_dir)
                    : parser.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(patched.data()),
                                                 unsigned(patched.size()), base_dir);
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) warnings.push_back("tinygltf: " + line);
    if (!ok || !err.empty()) {
        const std::string message = join_lines(err, "; ");
        throw SceneError("tinygltf: " + (message.empty() ? std::string("could not parse the file") : message));
    }
    for (const std::string& name : model.extensionsUsed) {
        if (name == "EXT_meshopt_compression") gltf::decode_meshopt_views(model, fallbacks);
        if (name == "KHR_draco_mesh_compression") gltf::decode_draco_primitives(model);
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

// Where a node draws: its world transform (at the render's time, or the shutter's centre) and, for motion blur, at
// the shutter's keys (SceneInstance::keys; empty for a node that stands still).
struct Placement {
    glm::dmat4 world;
    std::vector<glm::dmat4> keys;
    bool moves() const { return !keys.empty(); }
};

// `keys` kept only where some differ from `world`.
Placement place(const glm::dmat4& world, std::vector<glm::dmat4> keys) {
    for (const glm::dmat4& k : keys)
        if (k != world) return {world, std::move(keys)};
    return {world, {}};
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

// A camera node's motion from `open` to `close` (SceneCamera::moves): its origin along the line, its axes turned at
// a constant rate about one axis (the rotation between the two frames); world_from_camera becomes the pose halfway.
void set_camera_motion(SceneCamera& camera, const glm::dmat4& open, const glm::dmat4& close) {
    const glm::dmat3 r0(glm::normalize(glm::dvec3(open[0])), glm::normalize(glm::dvec3(open[1])),
                        glm::normalize(glm::dvec3(open[2])));
    const glm::dquat shorter = find_turn(open, close);
    const double angle = turn_angle(shorter);
    camera.moves = true;
    camera.motion_translation = glm::dvec3(close[3]) - glm::dvec3(open[3]);
    camera.motion_angle = angle;
    camera.motion_axis = angle > 0.0 ? glm::normalize(glm::dvec3(shorter.x, shorter.y, shorter.z)) : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dmat3 half = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.5 * angle, camera.motion_axis)) * r0;
    camera.world_from_camera = glm::dmat4(glm::dvec4(half[0], 0.0), glm::dvec4(half[1], 0.0), glm::dvec4(half[2], 0.0),
                                          glm::dvec4(0.5 * (glm::dvec3(open[3]) + glm::dvec3(close[3])), 1.0));
}

// Flattens the nodes of one scene into `scene`.
class Flattener {
public:
    Flattener(const tinygltf::Model& model, Scene& scene, int variant)
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

    // World transform of every node reached from the roots (the first path where a node is shared), the joints'
    // included: skins need them before the walk reaches the joints.
    void compute_node_worlds(const std::vector<int>& roots) {
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

    // Motion blur: the nodes' local transforms at the shutter's keys (the model posed at each: locals[key][node]);
    // without them every node keeps its transform over the shutter.
    void set_shutter_transforms(std::vector<std::vector<glm::dmat4>> locals) { local_keys_ = std::move(locals); }

    // parent_keys: the parent's world transforms at the shutter's keys (set_shutter_transforms; identities at a root).
    void visit_node(int index, const glm::dmat4& parent_world, int depth, const std::vector<glm::dmat4>& parent_keys) {
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
        if (node.mesh >= 0) record_mesh_uses(node, index, place(world, keys));
        if (node.camera >= 0) add_camera(node.camera, index, place(world, keys));
        if (const auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end())
            add_light(it->second, index, world);
        for (int child : node.children) {
            if (child < 0 || size_t(child) >= model_.nodes.size())
                throw SceneError(describe_node(model_, index) + " has child " + std::to_string(child) +
                                 ", which does not exist");
            visit_node(child, world, depth + 1, keys);
        }
        on_path_[size_t(index)] = 0;
    }

    // Places the triangles in render space (LoadOptions::rebase) and drops those without area there.
    void finish(bool rebase, Instancing instancing) {
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

private:
    // Rounds world positions (double) minus `origin` to float, keeping the triangles whose float cross
    // product is not zero: the GPU could neither hit them (zero determinant) nor give them a normal.
    // Instanced meshes stay in object space; their instances get the origin instead.
    void place_triangles(const glm::dvec3& origin) {
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

    void warn_once(const std::string& message) {
        if (warned_.emplace(message, 1).second) scene_.warnings.push_back(message);
    }

    // A node's mesh, once per EXT_mesh_gpu_instancing element if it has them (each placed node world x
    // translation x rotation x scale), drawn after the walk (add_recorded_meshes).
    void record_mesh_uses(const tinygltf::Node& node, int index, const Placement& place) {
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
            const int id = accessor.GetNumberAsInt();
            if (id >= 0 && size_t(id) < model_.accessors.size() && model_.accessors[size_t(id)].count > MAX_NODE_INSTANCES)
                throw SceneError(where + ": " + std::to_string(model_.accessors[size_t(id)].count) +
                                 " instances take the scene past " + std::to_string(MAX_NODE_INSTANCES) + " node instances");
            columns[a] = gltf::read_vectors(model_, accessor.GetNumberAsInt(), std::string(names[a]) + " of " + where,
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
    size_t estimate_triangles(int mesh_index) const {
        if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size()) return 0;
        size_t n = 0;
        for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives) {
            const auto position = prim.attributes.find("POSITION");
            const int accessor = prim.indices >= 0 ? prim.indices : position == prim.attributes.end() ? -1 : position->second;
            if (accessor >= 0 && size_t(accessor) < model_.accessors.size()) n += model_.accessors[size_t(accessor)].count / 3;
        }
        return n;
    }

    bool mesh_emits(int mesh_index) {
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
    void add_recorded_meshes(Instancing instancing) {
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
    std::string geometry_key(int mesh_index) {
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
    bool deforms(int mesh_index) const {
        if (mesh_index < 0 || size_t(mesh_index) >= model_.meshes.size()) return false;
        if (skinned_meshes_.count(mesh_index)) return true;
        for (const tinygltf::Primitive& prim : model_.meshes[size_t(mesh_index)].primitives)
            if (!prim.targets.empty()) return true;
        return false;
    }

    // `node`: the node drawing the mesh (its skin and morph weights), -1 for an instanced mesh's stored copy.
    void add_mesh(int mesh_index, const glm::dmat4& world, int node) {
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

    uint32_t material_index(int material, const std::string& where) {
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

    void add_primitive(const tinygltf::Primitive& prim, int mesh_index, int prim_index, const glm::dmat4& node_world,
                       int node) {
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

        // Normals transform with the inverse transpose; a mirroring transform flips the winding.
        const glm::dmat3 linear(world);
        const glm::dmat3 normal_from_object = glm::transpose(glm::inverse(linear));
        const bool mirrored = glm::determinant(linear) < 0.0;
        for (std::array<uint32_t, 3> tri : make_triangles(mode, indices)) {
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
            if (keep_attributes_) add_triangle_attributes(attributes, tri, linear, mirrored);
            triangle_material_.push_back(material);
            triangle_has_normals_.push_back(has_normals ? 1 : 0);
        }
    }

    // Morph targets (spec 3.7.2.2): each target's POSITION, NORMAL and TANGENT displacements times its weight, the
    // node's weights or else the mesh's (or an animation's, posed into the node before flattening).
    void apply_morph_targets(const tinygltf::Primitive& prim, int mesh_index, int node, const std::string& where,
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
    void apply_skin(const tinygltf::Primitive& prim, int node, const std::string& where, std::vector<glm::vec3>& positions,
                    std::vector<glm::vec3>& normals, std::vector<glm::vec4>& tangents) {
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
    static void rotate_to_lowest_vertex(std::array<uint32_t, 3>& tri, const std::vector<glm::vec3>& positions) {
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

    void add_camera(int camera_index, int node_index, const Placement& place) {
        const glm::dmat4& world = place.world;
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
        if (place.moves()) set_camera_motion(camera, place.keys.front(), place.keys.back());
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

// Motion blur: every node's local transform at the ends of K equal parts of the shutter (locals[k][node]), K doubled
// from 1 until no node turns more than MAX_TURN_PER_MOTION_SEGMENT between two keys, at most MAX_MOTION_SEGMENTS.
// Returns the largest turn between two keys (radians). The model's nodes are restored.
double key_shutter(tinygltf::Model& model, int animation, const LoadOptions& options,
                   std::vector<std::vector<glm::dmat4>>& locals) {
    const std::vector<tinygltf::Node> still = model.nodes;
    for (uint32_t segments = 1;; segments *= 2) {
        locals.assign(segments + 1, {});
        for (uint32_t k = 0; k <= segments; ++k) {
            const double s = double(k) / segments;
            gltf::pose_model(model, animation, options.time + (1.0 - s) * options.shutter_open + s * options.shutter_close);
            for (const tinygltf::Node& node : model.nodes) locals[k].push_back(local_transform(node));
            model.nodes = still;
        }
        double turn = 0.0;
        for (uint32_t k = 0; k < segments; ++k)
            for (size_t n = 0; n < model.nodes.size(); ++n)
                if (locals[k][n] != locals[k + 1][n]) {
                    const double a = turn_angle(find_turn(locals[k][n], locals[k + 1][n]));
                    if (std::isfinite(a)) turn = std::max(turn, a);
                }
        if (turn <= MAX_TURN_PER_MOTION_SEGMENT || segments >= MAX_MOTION_SEGMENTS) return turn;
    }
}

Scene load_unprefixed(const std::filesystem::path& file, const LoadOptions& options) {
    Scene scene;
    scene.source = file;
    tinygltf::Model model = read_model(file, scene.warnings);
    check_extensions(model, scene.warnings);
    std::vector<std::vector<glm::dmat4>> local_keys;  // motion blur: every node's transform at the shutter's keys
    if (options.animate || (options.has_shutter() && !model.animations.empty())) {
        const int animation = gltf::choose_animation(model, options.animation);
        if (animation < 0) throw SceneError("--time: the file has no animations");
        scene.animation = gltf::animation_name(model, animation);
        const gltf::AnimationRange range = gltf::animation_range(model, animation);
        scene.animation_start = range.start;
        scene.animation_end = range.end;
        if (options.has_shutter()) {
            const double turn = key_shutter(model, animation, options, local_keys);
            scene.motion_segments = uint32_t(local_keys.size() - 1);
            if (turn > MAX_TURN_PER_MOTION_SEGMENT) {
                char text[256];
                std::snprintf(text, sizeof text,
                              "a node turns by %.0f degrees in one of %u motion segments of the shutter: motion blur "
                              "follows its chord, which shrinks the mesh by up to %.1f%% there (a shorter shutter "
                              "shrinks less)",
                              glm::degrees(turn), scene.motion_segments, 100.0 * (1.0 - std::cos(0.5 * turn)));
                scene.warnings.push_back(text);
            }
        }
        gltf::pose_model(model, animation, options.time + 0.5 * (options.shutter_open + options.shutter_close));
    }
    for (size_t a = 0; a < model.animations.size(); ++a) scene.animations.push_back(gltf::animation_name(model, int(a)));
    scene.images = gltf::take_images(model);
    for (size_t m = 0; m < model.materials.size(); ++m) {
        scene.materials.push_back(gltf::convert_material(model, int(m), scene));
        scene.material_layers.push_back(gltf::convert_material_layers(model, int(m), scene));
        const FilmFresnelBound bound = bound_thin_film_fresnel(scene.materials.back(), scene.material_layers.back());
        scene.material_layers.back().iridescence_albedo_f0 = bound.a;
        scene.material_layers.back().iridescence_albedo_f90 = bound.b;
    }

    warn_about_shared_nodes(model, scene.warnings);
    Flattener flattener(model, scene, choose_variant(model, options.variant, scene.variants));
    const std::vector<int> roots = find_root_nodes(model, scene.warnings);
    check_node_instances(model, roots);
    flattener.compute_node_worlds(roots);
    const std::vector<glm::dmat4> root_keys(local_keys.size(), glm::dmat4(1.0));
    flattener.set_shutter_transforms(std::move(local_keys));
    for (int root : roots) flattener.visit_node(root, glm::dmat4(1.0), 0, root_keys);
    flattener.finish(options.rebase, options.instancing);
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
