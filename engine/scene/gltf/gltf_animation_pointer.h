// KHR_animation_pointer: the property an animation channel's JSON pointer (RFC 6901, into the glTF Asset Object Model)
// names, and how to set it on a tinygltf::Model. pose_model (gltf_animation.h) samples the channel and sets it before
// the model is converted, so materials, lights and cameras are read at the animation's time like node transforms.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// What a pointer names. `set` is empty for a property Fredholm reads but does not render (occlusionTexture's
// strength, a light's range) or does not know: `ignored_why` says which.
struct PointerTarget {
    static constexpr int ANY = 0;             // any number of floats per key (morph weights)
    static constexpr int FROM_ACCESSOR = -1;  // as many as the output accessor's type has (a material extension's)
    int components = 1;     // floats per keyframe value (1 to 4), ANY or FROM_ACCESSOR
    bool rotation = false;  // a unit quaternion: slerp between keys, normalised
    bool boolean = false;   // true where the sampled value is not 0 (KHR_node_visibility visible); STEP only
    std::function<void(const std::vector<double>&)> set;
    std::string ignored_why;
};

// Resolves `pointer` on `model` (which `set` then writes to; it must outlive the target). Throws SceneError for a
// pointer that is not a JSON pointer, or names an object that does not exist (a node, material, light or camera index
// out of range) or a typed property with another number of components than the glTF Object Model gives it.
PointerTarget resolve_animation_pointer(tinygltf::Model& model, const std::string& pointer);

}  // namespace fh::gltf
