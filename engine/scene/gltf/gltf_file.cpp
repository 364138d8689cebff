// read_model: a glTF or GLB file read safely (bounded regular files, GLB chunks and JSON nesting checked), then parsed.
#include "scene/gltf/gltf_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/gltf/gltf_draco.h"
#include "scene/gltf/gltf_material.h"
#include "scene/gltf/gltf_meshopt.h"
#include "scene/gltf/gltf_texture.h"
#include "scene/gltf/json_limits.h"
#include "scene/scene.h"

namespace fh::gltf {
namespace {

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

// KHR_animation_pointer channels have no target node, which this tinygltf requires of every channel (it would refuse
// the file): they get node -1, which pose_model reads as "no node" and the pointer then names the target.
bool patch_pointer_channels(nlohmann::json& doc) {
    bool patched = false;
    if (!doc.is_object() || !doc.contains("animations") || !doc["animations"].is_array()) return false;
    for (nlohmann::json& animation : doc["animations"]) {
        if (!animation.is_object() || !animation.contains("channels") || !animation["channels"].is_array()) continue;
        for (nlohmann::json& channel : animation["channels"]) {
            if (!channel.is_object() || !channel.contains("target") || !channel["target"].is_object()) continue;
            nlohmann::json& target = channel["target"];
            if (!target.contains("node") && target.value("path", nlohmann::json()) == "pointer") {
                target["node"] = -1;
                patched = true;
            }
        }
    }
    return patched;
}

// `json` patched where tinygltf would refuse what a compression extension (gltf_meshopt.h, gltf_draco.h) or
// KHR_animation_pointer allows; false when nothing needed it.
bool patch_for_decoders(std::string& json, std::vector<gltf::FallbackBuffer>& fallbacks) {
    if (json.find("EXT_meshopt_compression") == std::string::npos &&
        json.find("KHR_draco_mesh_compression") == std::string::npos &&
        json.find("KHR_animation_pointer") == std::string::npos)
        return false;
    nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_discarded()) return false;  // tinygltf reports bad JSON
    const bool meshopt = gltf::patch_meshopt_fallbacks(doc, fallbacks, MAX_FILE_BYTES);
    const bool draco = gltf::patch_draco_indices(doc);
    const bool pointers = patch_pointer_channels(doc);
    if (!meshopt && !draco && !pointers) return false;
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

// The file's JSON (`json`, as read_json_text gave it) patched for the compression extensions and animation pointers
// (patch_for_decoders),
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

// Refuses a file whose buffers and decoded textures would take more than the memory limit, before any texture is
// decoded (the buffers are read by then: at most 2 GiB each, as read_regular_file allows).
void check_load_memory(const tinygltf::Model& model, const gltf::PendingImages& pending, uint64_t memory_limit) {
    uint64_t buffer_bytes = 0;
    for (const tinygltf::Buffer& buffer : model.buffers) buffer_bytes += buffer.data.size();
    std::vector<MemoryUse> uses = gltf::decoded_image_uses(model, pending);
    uses.push_back({"buffers", buffer_bytes});
    const std::string problem = find_limit_problem(uses, memory_limit, "loading the scene");
    if (!problem.empty()) throw SceneError(problem);
}

}  // namespace

tinygltf::Model read_model(const std::filesystem::path& file, std::vector<std::string>& warnings, uint64_t memory_limit) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) throw SceneError("file not found");
    tinygltf::TinyGLTF parser;
    gltf::PendingImages pending;
    parser.SetImageLoader(&gltf::read_image_header, &pending);
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
    check_load_memory(model, pending, memory_limit);
    gltf::decode_pending_images(model, pending);
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

}  // namespace fh::gltf
