// Typed, range-checked reads of glTF accessors (glTF 2.0 spec section 3.6: buffers, views, accessors, sparse).
#include "scene/gltf/gltf_accessor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <tiny_gltf.h>

#include "scene/scene.h"

namespace fh::gltf {
namespace {

// Where bytes of one accessor live: element i starts at data + i * stride.
struct ElementBytes {
    const unsigned char* data = nullptr;  // null: no bufferView, elements are zero (sparse base)
    size_t stride = 0;
};

[[noreturn]] void fail(int index, const std::string& role, const std::string& problem) {
    throw SceneError(problem + " (accessor " + std::to_string(index) + ", " + role + ")");
}

size_t component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

bool is_index_type(int component_type) {
    return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

uint32_t load_uint(const unsigned char* p, int component_type) {
    if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
    if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
    }
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

// Locates `count` elements of `element_size` bytes at `offset` in buffer view `view_index`, `stride` apart
// (0: tightly packed), checking that the view lies in its buffer and the elements in the view.
ElementBytes locate(const tinygltf::Model& model, int view_index, size_t offset, size_t count,
                    size_t element_size, size_t stride, int index, const std::string& role,
                    const char* what) {
    const std::string prefix = *what ? std::string(what) + ": " : std::string();
    if (view_index < 0 || size_t(view_index) >= model.bufferViews.size())
        fail(index, role, prefix + "bufferView " + std::to_string(view_index) + " does not exist");
    const tinygltf::BufferView& view = model.bufferViews[size_t(view_index)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        fail(index, role, prefix + "buffer " + std::to_string(view.buffer) + " does not exist");
    const tinygltf::Buffer& buffer = model.buffers[size_t(view.buffer)];
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
        fail(index, role, prefix + "bufferView " + std::to_string(view_index) + " reaches past the end of buffer " +
                              std::to_string(view.buffer));
    if (stride == 0) stride = element_size;
    if (stride < element_size)
        fail(index, role, prefix + "byteStride " + std::to_string(stride) + " is smaller than an element");
    if (count > 0) {
        const size_t length = view.byteLength;
        const bool fits = offset <= length && element_size <= length - offset &&
                          (count - 1) <= (length - offset - element_size) / stride;
        if (!fits)
            fail(index, role, prefix + std::to_string(count) + " elements at byteOffset " + std::to_string(offset) +
                                  " do not fit in bufferView " + std::to_string(view_index));
    }
    ElementBytes bytes;
    bytes.data = buffer.data.data() + view.byteOffset + offset;
    bytes.stride = stride;
    return bytes;
}

// The accessor, once its count is known to be sane: the output array is allocated from the count before the
// elements are located, so a huge count must fail here rather than in the allocator.
const tinygltf::Accessor& find_accessor(const tinygltf::Model& model, int index, const std::string& role) {
    if (index < 0 || size_t(index) >= model.accessors.size()) fail(index, role, "accessor does not exist");
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    if (accessor.count > MAX_ACCESSOR_COUNT)
        fail(index, role, "count " + std::to_string(accessor.count) + " exceeds the limit of " +
                              std::to_string(MAX_ACCESSOR_COUNT) + " elements");
    return accessor;
}

// Calls write(element, bytes) for the dense elements, then for each sparse substitution (spec 3.6.2.3).
template <typename Write>
void visit_elements(const tinygltf::Model& model, int index, const std::string& role, size_t element_size,
                    Write write) {
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    if (accessor.bufferView >= 0) {
        const size_t stride = size_t(accessor.bufferView) < model.bufferViews.size()
                                  ? model.bufferViews[size_t(accessor.bufferView)].byteStride
                                  : 0;  // locate reports the missing view
        const ElementBytes dense = locate(model, accessor.bufferView, accessor.byteOffset, accessor.count,
                                          element_size, stride, index, role, "");
        for (size_t i = 0; i < accessor.count; ++i) write(i, dense.data + i * dense.stride);
    } else if (!accessor.sparse.isSparse) {
        fail(index, role, "accessor has neither a bufferView nor sparse data");
    }
    if (!accessor.sparse.isSparse) return;
    const auto& sparse = accessor.sparse;
    if (sparse.count < 0 || size_t(sparse.count) > accessor.count)
        fail(index, role, "sparse count " + std::to_string(sparse.count) + " exceeds the accessor count");
    if (!is_index_type(sparse.indices.componentType))
        fail(index, role, "sparse indices must be unsigned byte, short or int");
    const size_t count = size_t(sparse.count);
    const size_t index_size = component_size(sparse.indices.componentType);
    const ElementBytes indices = locate(model, sparse.indices.bufferView, size_t(sparse.indices.byteOffset), count,
                                        index_size, 0, index, role, "sparse indices");
    const ElementBytes values = locate(model, sparse.values.bufferView, size_t(sparse.values.byteOffset), count,
                                       element_size, 0, index, role, "sparse values");
    for (size_t k = 0; k < count; ++k) {
        const uint32_t target = load_uint(indices.data + k * indices.stride, sparse.indices.componentType);
        if (target >= accessor.count)
            fail(index, role, "sparse index " + std::to_string(target) + " is out of range (count " +
                                  std::to_string(accessor.count) + ")");
        write(target, values.data + k * values.stride);
    }
}

}  // namespace

const tinygltf::Value& json_member(const tinygltf::Value& object, const char* key) {
    static const tinygltf::Value null_value;
    return object.IsObject() && object.Has(key) ? object.Get(key) : null_value;
}

int read_json_index(const tinygltf::Value& value) {
    if (value.IsInt()) return std::max(value.Get<int>(), -1);
    if (!value.IsNumber()) return -1;
    const double v = value.Get<double>();
    return v >= 0.0 && v <= double(std::numeric_limits<int>::max()) && v == std::floor(v) ? int(v) : -1;
}

std::vector<glm::vec3> read_float3(const tinygltf::Model& model, int index, const std::string& role) {
    const tinygltf::Accessor& accessor = find_accessor(model, index, role);
    if (accessor.type != TINYGLTF_TYPE_VEC3 || accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail(index, role, "expected a float VEC3 accessor (quantized attributes are not supported)");
    std::vector<glm::vec3> out(accessor.count, glm::vec3(0.0f));
    visit_elements(model, index, role, 12, [&](size_t i, const unsigned char* p) {
        std::memcpy(&out[i], p, 12);
    });
    return out;
}

std::vector<glm::dmat4> read_matrices(const tinygltf::Model& model, int index, const std::string& role) {
    const tinygltf::Accessor& accessor = find_accessor(model, index, role);
    if (accessor.type != TINYGLTF_TYPE_MAT4 || accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail(index, role, "expected a float MAT4 accessor");
    std::vector<glm::dmat4> out(accessor.count, glm::dmat4(1.0));
    visit_elements(model, index, role, 64, [&](size_t i, const unsigned char* p) {
        float m[16];
        std::memcpy(m, p, 64);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) out[i][c][r] = m[4 * c + r];
    });
    for (const glm::dmat4& m : out)
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r])) fail(index, role, "a matrix is not finite");
    return out;
}

int component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

namespace {

// One component as float: float as stored; integers normalized as spec 3.11 ("Animations", the
// normalization table) says when `normalized`, else converted as they are (KHR_mesh_quantization).
float load_component(const unsigned char* p, int component_type, bool normalized) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(*p) / 255.0f : float(*p);
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float v = float(int8_t(*p));
            return normalized ? std::max(v / 127.0f, -1.0f) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? float(v) / 65535.0f : float(v);
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
        }
        default: return 0.0f;
    }
}

}  // namespace

std::vector<glm::vec4> read_vectors(const tinygltf::Model& model, int index, const std::string& role,
                                    int min_components, int max_components, bool integers_allowed) {
    const tinygltf::Accessor& accessor = find_accessor(model, index, role);
    const int n = component_count(accessor.type);
    const int type = accessor.componentType;
    const bool is_float = type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool is_small_int = type == TINYGLTF_COMPONENT_TYPE_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              type == TINYGLTF_COMPONENT_TYPE_SHORT || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (n < min_components || n > max_components)
        fail(index, role, "expected a VEC" + std::to_string(min_components) +
                              (max_components > min_components ? " to VEC" + std::to_string(max_components) : "") +
                              " accessor");
    if (!is_float && !(integers_allowed && is_small_int))
        fail(index, role, integers_allowed ? "expected float or (normalized) byte/short components"
                                           : "expected float components");
    const size_t size = component_size(type);
    std::vector<glm::vec4> out(accessor.count, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    visit_elements(model, index, role, size * size_t(n), [&](size_t i, const unsigned char* p) {
        for (int c = 0; c < n; ++c) out[i][c] = load_component(p + size_t(c) * size, type, accessor.normalized);
    });
    return out;
}

std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& role) {
    const tinygltf::Accessor& accessor = find_accessor(model, index, role);
    if (accessor.type != TINYGLTF_TYPE_SCALAR || !is_index_type(accessor.componentType))
        fail(index, role, "indices must be unsigned byte, short or int SCALARs");
    const int type = accessor.componentType;
    std::vector<uint32_t> out(accessor.count, 0u);
    visit_elements(model, index, role, component_size(type), [&](size_t i, const unsigned char* p) {
        out[i] = load_uint(p, type);
    });
    return out;
}

}  // namespace fh::gltf
