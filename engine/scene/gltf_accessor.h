// Typed, range-checked reads of glTF accessors (byteStride, sparse substitution), used by the glTF loader.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// Reads accessor `index` as float VEC3 elements; `role` (e.g. "POSITION of mesh 2 primitive 0") is named in
// errors. Throws SceneError (without the file name; the loader adds it) when the accessor is not float VEC3
// or reaches outside its buffer view or buffer.
std::vector<glm::vec3> read_float3(const tinygltf::Model& model, int index, const std::string& role);

// Reads accessor `index` as unsigned SCALAR indices (UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT).
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& role);

}  // namespace fh::gltf
