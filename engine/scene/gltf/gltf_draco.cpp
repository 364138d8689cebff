// KHR_draco_mesh_compression (spec: KhronosGroup/glTF extensions/2.0/Khronos/KHR_draco_mesh_compression) with
// Debian's libdraco.
#include "scene/gltf/gltf_draco.h"

#include <cstring>
#include <string>

#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"
#include "scene/scene.h"

namespace fh::gltf {
namespace {

// Appends `bytes` as a new buffer with one view, and points `accessor` at it.
void attach(tinygltf::Model& model, tinygltf::Accessor& accessor, std::vector<unsigned char> bytes) {
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes);
    tinygltf::BufferView view;
    view.buffer = int(model.buffers.size());
    view.byteOffset = 0;
    view.byteLength = buffer.data.size();
    model.buffers.push_back(std::move(buffer));
    accessor.bufferView = int(model.bufferViews.size());
    accessor.byteOffset = 0;
    accessor.sparse.isSparse = false;
    model.bufferViews.push_back(view);
}

// One attribute's values converted to the accessor's component type (float, or the integer types of
// KHR_mesh_quantization; Draco keeps integer attributes as the file's integers, normalized or not).
template <typename T>
std::vector<unsigned char> convert_attribute(const draco::Mesh& mesh, const draco::PointAttribute& attribute, int components) {
    std::vector<unsigned char> out(size_t(mesh.num_points()) * size_t(components) * sizeof(T));
    T* values = reinterpret_cast<T*>(out.data());
    for (draco::PointIndex p(0); p < mesh.num_points(); ++p)
        attribute.ConvertValue<T>(attribute.mapped_index(p), int8_t(components), values + size_t(p.value()) * size_t(components));
    return out;
}

void decode_primitive(tinygltf::Model& model, tinygltf::Primitive& prim, const tinygltf::Value& ext,
                      const std::string& where) {
    const tinygltf::Value& view_value = ext.Get("bufferView");
    if (!view_value.IsInt() && !view_value.IsNumber()) throw SceneError(where + ": KHR_draco_mesh_compression has no bufferView");
    const int view_index = read_json_index(view_value);
    if (view_index < 0 || size_t(view_index) >= model.bufferViews.size())
        throw SceneError(where + ": KHR_draco_mesh_compression bufferView " + std::to_string(view_index) + " does not exist");
    const tinygltf::BufferView& view = model.bufferViews[size_t(view_index)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size() ||
        view.byteOffset > model.buffers[size_t(view.buffer)].data.size() ||
        view.byteLength > model.buffers[size_t(view.buffer)].data.size() - view.byteOffset)
        throw SceneError(where + ": KHR_draco_mesh_compression bufferView " + std::to_string(view_index) +
                         " reaches past the end of its buffer");
    draco::DecoderBuffer stream;
    stream.Init(reinterpret_cast<const char*>(model.buffers[size_t(view.buffer)].data.data() + view.byteOffset),
                view.byteLength);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&stream);
    if (!decoded.ok())
        throw SceneError(where + ": the Draco stream cannot be decoded (" + decoded.status().error_msg_string() + ")");
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();

    if (prim.indices >= 0) {
        if (size_t(prim.indices) >= model.accessors.size()) throw SceneError(where + ": the indices accessor does not exist");
        tinygltf::Accessor& accessor = model.accessors[size_t(prim.indices)];
        const size_t count = size_t(mesh->num_faces()) * 3;
        if (accessor.count != count)
            throw SceneError(where + ": the Draco stream has " + std::to_string(count) + " indices, the accessor " +
                             std::to_string(accessor.count));
        const bool wide = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        const bool narrow = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
        std::vector<unsigned char> bytes(count * (wide ? 4 : narrow ? 1 : 2));
        for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const uint32_t index = mesh->face(f)[k].value();
                const size_t i = size_t(f.value()) * 3 + size_t(k);
                if (wide) std::memcpy(bytes.data() + 4 * i, &index, 4);
                else if (narrow) bytes[i] = uint8_t(index);
                else {
                    const uint16_t v = uint16_t(index);
                    std::memcpy(bytes.data() + 2 * i, &v, 2);
                }
                if ((narrow && index > 0xffu) || (!wide && !narrow && index > 0xffffu))
                    throw SceneError(where + ": a Draco index does not fit the indices accessor's type");
            }
        attach(model, accessor, std::move(bytes));
    }

    const tinygltf::Value& attributes = ext.Get("attributes");
    if (!attributes.IsObject()) throw SceneError(where + ": KHR_draco_mesh_compression has no attributes");
    for (const std::string& name : attributes.Keys()) {
        const auto it = prim.attributes.find(name);
        if (it == prim.attributes.end() || it->second < 0 || size_t(it->second) >= model.accessors.size())
            throw SceneError(where + ": Draco attribute " + name + " has no accessor in the primitive");
        const tinygltf::Value& id = attributes.Get(name);
        if (!id.IsInt() && !id.IsNumber()) throw SceneError(where + ": Draco attribute " + name + " has no id");
        const draco::PointAttribute* attribute = mesh->GetAttributeByUniqueId(uint32_t(read_json_index(id)));
        if (attribute == nullptr)
            throw SceneError(where + ": the Draco stream has no attribute " + std::to_string(read_json_index(id)) + " (" + name + ")");
        tinygltf::Accessor& accessor = model.accessors[size_t(it->second)];
        const int components = component_count(accessor.type);
        if (accessor.count != size_t(mesh->num_points()) || components == 0 || attribute->num_components() < 1)
            throw SceneError(where + ": Draco attribute " + name + " has " + std::to_string(mesh->num_points()) +
                             " points, the accessor " + std::to_string(accessor.count));
        std::vector<unsigned char> bytes;
        switch (accessor.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: bytes = convert_attribute<float>(*mesh, *attribute, components); break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: bytes = convert_attribute<int8_t>(*mesh, *attribute, components); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: bytes = convert_attribute<uint8_t>(*mesh, *attribute, components); break;
            case TINYGLTF_COMPONENT_TYPE_SHORT: bytes = convert_attribute<int16_t>(*mesh, *attribute, components); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: bytes = convert_attribute<uint16_t>(*mesh, *attribute, components); break;
            default: throw SceneError(where + ": Draco attribute " + name + " has an unsupported component type");
        }
        attach(model, accessor, std::move(bytes));
    }
}

}  // namespace

bool patch_draco_indices(nlohmann::json& doc) {
    if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors") ||
        !doc["accessors"].is_array())
        return false;  // tinygltf reports what is wrong
    nlohmann::json& accessors = doc["accessors"];
    bool changed = false;
    for (nlohmann::json& mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (nlohmann::json& prim : mesh["primitives"]) {
            if (!prim.is_object() || !prim.contains("indices") || !prim["indices"].is_number_integer()) continue;
            const auto ext = prim.find("extensions");
            if (ext == prim.end() || !ext->is_object() || !ext->contains("KHR_draco_mesh_compression")) continue;
            const nlohmann::json& draco = (*ext)["KHR_draco_mesh_compression"];
            const int64_t index = prim["indices"].get<int64_t>();
            if (!draco.is_object() || !draco.contains("bufferView") || !draco["bufferView"].is_number_integer() ||
                index < 0 || size_t(index) >= accessors.size() || !accessors[size_t(index)].is_object() ||
                accessors[size_t(index)].contains("bufferView"))
                continue;
            accessors[size_t(index)]["bufferView"] = draco["bufferView"];
            changed = true;
        }
    }
    return changed;
}

void decode_draco_primitives(tinygltf::Model& model) {
    for (size_t m = 0; m < model.meshes.size(); ++m)
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive& prim = model.meshes[m].primitives[p];
            const auto it = prim.extensions.find("KHR_draco_mesh_compression");
            if (it == prim.extensions.end() || !it->second.IsObject()) continue;
            decode_primitive(model, prim, it->second,
                             "mesh " + std::to_string(m) + " primitive " + std::to_string(p));
        }
}

}  // namespace fh::gltf
