// glTF animation (spec 3.11): a model posed at a time, its node TRS and morph weights sampled from one animation's
// channels (STEP, LINEAR with slerp for rotations, CUBICSPLINE). The loader poses the model before flattening it, so
// everything downstream (skins, morph targets, cameras, lights, the BVH) sees the scene at that time.
#pragma once
#include <string>

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

// Sets every node the animation targets to its pose at `time` (seconds): translation, rotation and scale, or the
// morph target weights. Before the first keyframe a channel holds its first value, after the last its last. Throws
// SceneError for a malformed channel or sampler (missing accessors, times not increasing, output counts that do not
// match, a channel on a node given by a matrix).
void pose_model(tinygltf::Model& model, int animation, double time);

}  // namespace fh::gltf
