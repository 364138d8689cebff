// glTF animation (spec 3.11): a model posed at a time, its node TRS and morph weights (and what KHR_animation_pointer
// targets) sampled from one animation's channels (STEP, LINEAR with slerp for rotations, CUBICSPLINE). The loader poses the model before flattening it, so
// everything downstream (skins, morph targets, cameras, lights, the BVH) sees the scene at that time.
#pragma once
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// The animation `wanted` names: "" the first (-1 when the file has none), a decimal index, or a name. Throws SceneError
// naming the file's animations for one it does not have.
int choose_animation(const tinygltf::Model& model, const std::string& wanted);

// The animation's name, or "animation N" for an unnamed one.
std::string animation_name(const tinygltf::Model& model, int animation);

// First and last keyframe time of the animation over all its samplers, seconds.
struct AnimationRange {
    double start = 0.0, end = 0.0;
};
AnimationRange animation_range(const tinygltf::Model& model, int animation);

// Sets every property the animation targets to its value at `time` (seconds): node translation, rotation and scale,
// morph target weights, and through KHR_animation_pointer material factors and texture transforms, light colour,
// intensity and spot angles, camera fields of view and extents, node visibility (gltf_animation_pointer.h). Before
// the first keyframe a channel holds its first value, after the last its last. A pointer to a property Fredholm does
// not render is skipped, warned once in `warnings` when given. Throws SceneError for a malformed channel or sampler
// (missing accessors, times not increasing, output counts that do not match, a channel on a node given by a matrix,
// a pointer to an object that does not exist).
void pose_model(tinygltf::Model& model, int animation, double time, std::vector<std::string>* warnings = nullptr);

}  // namespace fh::gltf
