// EXT_meshopt_compression (meshoptimizer's vertex and index codecs, with its filters): compressed buffer views
// are decoded into their fallback buffers, so that the rest of the loader reads plain accessors.
#pragma once
#include <cstddef>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// A fallback buffer (no data in the file: every view of it is compressed) and the size it must have.
struct FallbackBuffer {
    int buffer = -1;
    size_t byte_length = 0;
};

// The glTF document `doc` made loadable by tinygltf when it uses EXT_meshopt_compression: a fallback buffer
// without a uri (tinygltf refuses one) gets a 4-byte data URI, and its real size is remembered in `fallbacks`.
// Returns whether it changed `doc`. Throws SceneError for a fallback buffer larger than `max_bytes`.
bool patch_meshopt_fallbacks(nlohmann::json& doc, std::vector<FallbackBuffer>& fallbacks, size_t max_bytes);

// Decodes every compressed buffer view of `model` into its (fallback) buffer, after sizing the fallbacks.
// Throws SceneError naming the view for a stream that reaches outside its buffer, an unknown mode or filter,
// a stride the mode does not allow, or data the decoder rejects (corrupt or truncated).
void decode_meshopt_views(tinygltf::Model& model, const std::vector<FallbackBuffer>& fallbacks);

}  // namespace fh::gltf
