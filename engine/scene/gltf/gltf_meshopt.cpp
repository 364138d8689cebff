// EXT_meshopt_compression: JSON patch for tinygltf, then decoding with libmeshoptimizer (spec:
// KhronosGroup/glTF extensions/2.0/Vendor/EXT_meshopt_compression).
#include "scene/gltf/gltf_meshopt.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/scene.h"

namespace fh::gltf {
namespace {

const char* const EXTENSION = "EXT_meshopt_compression";

bool uses_extension(const nlohmann::json& doc) {
    const auto used = doc.find("extensionsUsed");
    if (used == doc.end() || !used->is_array()) return false;
    for (const auto& name : *used)
        if (name.is_string() && name.get<std::string>() == EXTENSION) return true;
    return false;
}

size_t read_size(const tinygltf::Value& object, const char* key, const std::string& where) {
    if (!object.Has(key) || !(object.Get(key).IsInt() || object.Get(key).IsNumber()))
        throw SceneError(where + ": " + key + " is missing");
    const double v = object.Get(key).GetNumberAsDouble();
    if (!(v >= 0.0 && v <= 9007199254740992.0) || v != double(size_t(v)))
        throw SceneError(where + ": " + key + " is not a valid size");
    return size_t(v);
}

std::string read_string(const tinygltf::Value& object, const char* key, const char* fallback) {
    if (!object.Has(key)) return fallback;
    return object.Get(key).IsString() ? object.Get(key).Get<std::string>() : std::string();
}

void decode_view(tinygltf::Model& model, size_t view_index, const tinygltf::Value& ext) {
    const std::string where = std::string(EXTENSION) + " of bufferView " + std::to_string(view_index);
    tinygltf::BufferView& view = model.bufferViews[view_index];
    const size_t source_buffer = read_size(ext, "buffer", where);
    const size_t source_offset = ext.Has("byteOffset") ? read_size(ext, "byteOffset", where) : 0;
    const size_t source_length = read_size(ext, "byteLength", where);
    const size_t stride = read_size(ext, "byteStride", where);
    const size_t count = read_size(ext, "count", where);
    const std::string mode = read_string(ext, "mode", "");
    const std::string filter = read_string(ext, "filter", "NONE");
    if (source_buffer >= model.buffers.size())
        throw SceneError(where + ": buffer " + std::to_string(source_buffer) + " does not exist");
    const std::vector<unsigned char>& source = model.buffers[source_buffer].data;
    if (source_offset > source.size() || source_length > source.size() - source_offset)
        throw SceneError(where + ": the compressed stream reaches past the end of buffer " + std::to_string(source_buffer));
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        throw SceneError(where + ": its buffer does not exist");
    std::vector<unsigned char>& target = model.buffers[size_t(view.buffer)].data;
    if (stride == 0 || stride > 256 || count > (size_t(1) << 28))
        throw SceneError(where + ": byteStride " + std::to_string(stride) + " or count " + std::to_string(count) +
                         " out of range");
    const size_t bytes = stride * count;
    if (view.byteOffset > target.size() || bytes > target.size() - view.byteOffset || bytes > view.byteLength)
        throw SceneError(where + ": " + std::to_string(count) + " elements of " + std::to_string(stride) +
                         " bytes do not fit in the view");
    unsigned char* out = target.data() + view.byteOffset;
    const unsigned char* in = source.data() + source_offset;
    int rc = 0;
    if (mode == "ATTRIBUTES") {
        if (stride % 4 != 0) throw SceneError(where + ": ATTRIBUTES need a byteStride that is a multiple of 4");
        rc = meshopt_decodeVertexBuffer(out, count, stride, in, source_length);
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4) throw SceneError(where + ": " + mode + " need a byteStride of 2 or 4");
        if (mode == "TRIANGLES" && count % 3 != 0) throw SceneError(where + ": TRIANGLES need a count divisible by 3");
        rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out, count, stride, in, source_length)
                                 : meshopt_decodeIndexSequence(out, count, stride, in, source_length);
    } else {
        throw SceneError(where + ": unknown mode '" + mode + "'");
    }
    if (rc != 0) throw SceneError(where + ": the " + mode + " stream cannot be decoded (corrupt or truncated)");
    if (filter == "NONE") return;
    if (mode != "ATTRIBUTES") throw SceneError(where + ": filter " + filter + " needs mode ATTRIBUTES");
    if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) meshopt_decodeFilterOct(out, count, stride);
    else if (filter == "QUATERNION" && stride == 8) meshopt_decodeFilterQuat(out, count, stride);
    else if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out, count, stride);
    else throw SceneError(where + ": filter '" + filter + "' with byteStride " + std::to_string(stride) + " is not valid");
}

}  // namespace

bool patch_meshopt_fallbacks(nlohmann::json& doc, std::vector<FallbackBuffer>& fallbacks, size_t max_bytes) {
    if (!doc.is_object() || !uses_extension(doc)) return false;
    auto buffers = doc.find("buffers");
    if (buffers == doc.end() || !buffers->is_array()) return false;
    bool changed = false;
    for (size_t i = 0; i < buffers->size(); ++i) {
        nlohmann::json& buffer = (*buffers)[i];
        if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions")) continue;
        const nlohmann::json& ext = buffer["extensions"];
        if (!ext.is_object() || !ext.contains(EXTENSION)) continue;
        const nlohmann::json& length = buffer["byteLength"];
        if (!length.is_number_unsigned() && !length.is_number_integer()) continue;  // tinygltf reports it
        const uint64_t bytes = length.get<uint64_t>();
        if (bytes > max_bytes)
            throw SceneError(std::string(EXTENSION) + ": fallback buffer " + std::to_string(i) + " of " +
                             std::to_string(bytes) + " bytes is larger than the limit of " + std::to_string(max_bytes));
        fallbacks.push_back({int(i), size_t(bytes)});
        buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";  // tinygltf refuses an empty one
        buffer["byteLength"] = 4;
        changed = true;
    }
    return changed;
}

void decode_meshopt_views(tinygltf::Model& model, const std::vector<FallbackBuffer>& fallbacks) {
    for (const FallbackBuffer& f : fallbacks)
        if (f.buffer >= 0 && size_t(f.buffer) < model.buffers.size()) model.buffers[size_t(f.buffer)].data.assign(f.byte_length, 0);
    for (size_t v = 0; v < model.bufferViews.size(); ++v) {
        const auto it = model.bufferViews[v].extensions.find(EXTENSION);
        if (it != model.bufferViews[v].extensions.end() && it->second.IsObject()) decode_view(model, v, it->second);
    }
}

}  // namespace fh::gltf
