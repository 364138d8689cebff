// KHR_draco_mesh_compression: each compressed primitive is decoded with Google's Draco, and its accessors are
// pointed at the decoded data, so that the rest of the loader reads plain accessors.
#pragma once

#include <nlohmann/json_fwd.hpp>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// The glTF document `doc` made loadable by tinygltf when it uses KHR_draco_mesh_compression: tinygltf refuses
// an indices accessor without a bufferView, which the extension allows, so each such accessor of a compressed
// primitive is pointed at the primitive's Draco view until decode_draco_primitives gives it its own. Returns
// whether it changed `doc`.
bool patch_draco_indices(nlohmann::json& doc);

// Decodes every primitive of `model` that carries KHR_draco_mesh_compression: the indices and each attribute the
// extension lists are written, in their accessors' component types, to a new buffer and buffer view. Throws
// SceneError naming the mesh and primitive for a missing or corrupt stream, an attribute id the stream does not
// have, or a decoded count that differs from the accessor's.
void decode_draco_primitives(tinygltf::Model& model);

}  // namespace fh::gltf
