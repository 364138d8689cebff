// Reads a glTF or GLB file into a tinygltf::Model safely (regular files of bounded size, checked before parsing).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// The file parsed by tinygltf: its .bin buffers and images read only if they are regular files of at most 2 GiB,
// a GLB's BIN chunk and the JSON's nesting checked first, and EXT_meshopt_compression buffer views and
// KHR_draco_mesh_compression primitives decoded. tinygltf's warnings are appended to `warnings`. Throws SceneError
// (without the file name; load_gltf adds it) when the file is missing, refused or does not parse.
// Textures are decoded after the parse, once their declared sizes show that they fit `memory_limit` (bytes; 0: no
// limit) together with the buffers; else SceneError names the largest.
tinygltf::Model read_model(const std::filesystem::path& file, std::vector<std::string>& warnings, uint64_t memory_limit = 0);

// Throws SceneError for an extension in extensionsRequired that this loader does not implement; warns about one
// that is only in extensionsUsed.
void check_extensions(const tinygltf::Model& model, std::vector<std::string>& warnings);

}  // namespace fh::gltf
