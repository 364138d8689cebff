// Typed, range-checked reads of glTF accessors (byteStride, sparse substitution), used by the glTF loader.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tinygltf {
class Model;
class Value;
}

namespace fh::gltf {

// An index an extension's JSON gives (tinygltf leaves extensions as values): an integer, or a real of integral value, in
// [0, INT_MAX]; else -1, which the caller's range check refuses. (tinygltf's GetNumberAsInt converts any real to int,
// undefined behaviour past its range: a fuzzer finding, tests/fuzz/regressions/ub_draco_buffer_view_3e38.gltf.)
int read_json_index(const tinygltf::Value& value);

// `object`'s member `key`, or a null value where `object` is not an object or lacks it (tinygltf's Value::Get asserts
// on a non-object: a fuzzer finding, tests/fuzz/regressions/assert_variant_not_an_object.glb).
const tinygltf::Value& json_member(const tinygltf::Value& object, const char* key);

// Accessors with more elements are refused before anything is allocated: 2^27 elements is far beyond what the
// renderer can hold (see render/memory_estimate.h), and keeps every element index well inside 32 bits.
constexpr size_t MAX_ACCESSOR_COUNT = size_t(1) << 27;

// Reads accessor `index` as float VEC3 elements; `role` (e.g. "POSITION of mesh 2 primitive 0") is named in
// errors. Throws SceneError (without the file name; the loader adds it) when the accessor is not float VEC3
// or reaches outside its buffer view or buffer, or has more than MAX_ACCESSOR_COUNT elements.
std::vector<glm::vec3> read_float3(const tinygltf::Model& model, int index, const std::string& role);

// Reads accessor `index` as float vectors of min_components to max_components components (VEC2..VEC4; missing
// components read (0, 0, 0, 1)). Float components always; with `integers_allowed` also byte and short
// components, normalized where the accessor says so (KHR_mesh_quantization: texture coordinates, colours).
std::vector<glm::vec4> read_vectors(const tinygltf::Model& model, int index, const std::string& role,
                                    int min_components, int max_components, bool integers_allowed);

// Reads accessor `index` as float MAT4 elements (column-major, as glTF stores them), e.g. a skin's inverse bind
// matrices.
std::vector<glm::dmat4> read_matrices(const tinygltf::Model& model, int index, const std::string& role);

// Components of a tinygltf accessor type (SCALAR 1 .. VEC4 4; 0 for matrices and unknown types).
int component_count(int type);

// Reads accessor `index` as unsigned SCALAR indices (UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT).
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& role);

}  // namespace fh::gltf
