// Keyframe sampling of glTF animations (spec 3.11 and Appendix C: interpolation).
#include "scene/gltf/gltf_animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "scene/gltf/gltf_accessor.h"
#include "scene/gltf/gltf_animation_pointer.h"
#include "scene/scene.h"

namespace fh::gltf {
namespace {

// One channel's keys: times, and `width` floats per output element (3 per key for CUBICSPLINE: in-tangent, value,
// out-tangent).
struct Track {
    std::vector<double> times;
    std::vector<double> values;  // keys x elements x width
    size_t width = 0;            // floats per element: 1 to 4, or the number of morph targets
    std::string interpolation;
};

std::string describe(const tinygltf::Model& model, int animation, size_t channel) {
    return animation_name(model, animation) + " channel " + std::to_string(channel);
}

// The number of components of accessor `index`'s type (1 for one that does not exist: read_vectors reports it).
int accessor_components(const tinygltf::Model& model, int index) {
    if (index < 0 || size_t(index) >= model.accessors.size()) return 1;
    const int n = tinygltf::GetNumComponentsInType(uint32_t(model.accessors[size_t(index)].type));
    return n >= 1 && n <= 4 ? n : 1;
}

Track read_track(const tinygltf::Model& model, const tinygltf::AnimationSampler& sampler, const PointerTarget& target,
                 const std::string& where) {
    Track track;
    track.interpolation = sampler.interpolation.empty() ? "LINEAR" : sampler.interpolation;
    if (track.interpolation != "LINEAR" && track.interpolation != "STEP" && track.interpolation != "CUBICSPLINE")
        throw SceneError(where + ": unknown interpolation '" + track.interpolation + "'");
    if (target.boolean && track.interpolation != "STEP")
        throw SceneError(where + ": a boolean property is animated with " + track.interpolation +
                         " interpolation (KHR_animation_pointer requires STEP)");
    if (target.boolean && (sampler.output < 0 || size_t(sampler.output) >= model.accessors.size() ||
                           model.accessors[size_t(sampler.output)].componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE))
        throw SceneError(where + ": a boolean property needs unsigned byte outputs (KHR_animation_pointer)");
    for (const glm::vec4& t : read_vectors(model, sampler.input, "input of " + where, 1, 1, false)) {
        if (!std::isfinite(t.x)) throw SceneError(where + ": a keyframe time is not finite");
        if (!track.times.empty() && !(t.x > track.times.back()))
            throw SceneError(where + ": keyframe times do not increase");
        track.times.push_back(t.x);
    }
    if (track.times.empty()) throw SceneError(where + ": no keyframes");
    const bool any_count = target.components == PointerTarget::ANY;
    const int components = target.components == PointerTarget::FROM_ACCESSOR ? accessor_components(model, sampler.output)
                           : any_count                                      ? 1
                                                                            : target.components;
    // Integer outputs: rotations and weights (spec 3.11), and what only a pointer reaches (the Object Model).
    const bool integers = target.rotation || any_count || target.boolean || target.components < 0;
    const std::vector<glm::vec4> out =
        read_vectors(model, sampler.output, "output of " + where, components, components, integers);
    const size_t per_key = track.interpolation == "CUBICSPLINE" ? 3 : 1;
    const size_t keys = track.times.size();
    if (any_count) {
        if (out.size() % (keys * per_key) != 0 || out.empty())
            throw SceneError(where + ": " + std::to_string(out.size()) + " weights do not divide into " +
                             std::to_string(keys) + " keyframes");
        track.width = out.size() / (keys * per_key);
        for (const glm::vec4& v : out) track.values.push_back(v.x);
    } else {
        if (out.size() != keys * per_key)
            throw SceneError(where + ": " + std::to_string(out.size()) + " outputs for " + std::to_string(keys) +
                             " keyframes (" + track.interpolation + " needs " + std::to_string(keys * per_key) + ")");
        track.width = size_t(components);
        for (const glm::vec4& v : out)
            for (int c = 0; c < components; ++c) track.values.push_back(v[c]);
    }
    for (double v : track.values)
        if (!std::isfinite(v)) throw SceneError(where + ": an output value is not finite");
    return track;
}

// Element `element` (0: in-tangent, 1: value, 2: out-tangent for CUBICSPLINE; 0 otherwise) of key `key`.
std::vector<double> element(const Track& t, size_t key, size_t element) {
    const size_t per_key = t.interpolation == "CUBICSPLINE" ? 3 : 1;
    const size_t first = (key * per_key + element) * t.width;
    return std::vector<double>(t.values.begin() + long(first), t.values.begin() + long(first + t.width));
}

// Spherical linear interpolation of unit quaternions (x, y, z, w) along the shorter arc (spec Appendix C).
std::vector<double> slerp(std::vector<double> a, std::vector<double> b, double s) {
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0.0) {
        for (double& x : b) x = -x;
        d = -d;
    }
    std::vector<double> out(4);
    if (d > 0.9995) {  // nearly parallel: linear, then normalised
        for (int i = 0; i < 4; ++i) out[i] = a[i] + s * (b[i] - a[i]);
    } else {
        const double angle = std::acos(d), sin_angle = std::sin(angle);
        const double wa = std::sin((1.0 - s) * angle) / sin_angle, wb = std::sin(s * angle) / sin_angle;
        for (int i = 0; i < 4; ++i) out[i] = wa * a[i] + wb * b[i];
    }
    return out;
}

void normalize(std::vector<double>& q) {
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0.0 && std::isfinite(n))
        for (double& x : q) x /= n;
    else q = {0.0, 0.0, 0.0, 1.0};
}

std::vector<double> sample(const Track& t, double time, bool rotation) {
    const size_t keys = t.times.size();
    const size_t value = t.interpolation == "CUBICSPLINE" ? 1 : 0;
    std::vector<double> out;
    if (keys == 1 || time <= t.times.front()) out = element(t, 0, value);
    else if (time >= t.times.back()) out = element(t, keys - 1, value);
    else {
        const size_t k = size_t(std::upper_bound(t.times.begin(), t.times.end(), time) - t.times.begin()) - 1;
        const double t0 = t.times[k], dt = t.times[k + 1] - t0, s = (time - t0) / dt;
        if (t.interpolation == "STEP") {
            out = element(t, k, 0);
        } else if (t.interpolation == "LINEAR") {
            const std::vector<double> a = element(t, k, 0), b = element(t, k + 1, 0);
            if (rotation) out = slerp(a, b, s);
            else {
                out.resize(t.width);
                for (size_t i = 0; i < t.width; ++i) out[i] = a[i] + s * (b[i] - a[i]);
            }
        } else {  // CUBICSPLINE: Hermite with the tangents scaled by the interval (spec Appendix C)
            const std::vector<double> v0 = element(t, k, 1), b0 = element(t, k, 2), a1 = element(t, k + 1, 0),
                                      v1 = element(t, k + 1, 1);
            const double s2 = s * s, s3 = s2 * s;
            const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
            out.resize(t.width);
            for (size_t i = 0; i < t.width; ++i) out[i] = h00 * v0[i] + h10 * dt * b0[i] + h01 * v1[i] + h11 * dt * a1[i];
        }
    }
    if (rotation) normalize(out);
    return out;
}

}  // namespace

std::string animation_name(const tinygltf::Model& model, int animation) {
    if (animation < 0 || size_t(animation) >= model.animations.size()) return "no animation";
    const std::string& name = model.animations[size_t(animation)].name;
    return name.empty() ? "animation " + std::to_string(animation) : "animation " + std::to_string(animation) + " '" + name + "'";
}

int choose_animation(const tinygltf::Model& model, const std::string& wanted) {
    if (wanted.empty()) return model.animations.empty() ? -1 : 0;
    if (std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; }) && wanted.size() < 9) {
        const size_t index = std::stoul(wanted);
        if (index < model.animations.size()) return int(index);
    }
    for (size_t a = 0; a < model.animations.size(); ++a)
        if (model.animations[a].name == wanted) return int(a);
    std::string known;
    for (size_t a = 0; a < model.animations.size(); ++a)
        known += (known.empty() ? "" : ", ") + animation_name(model, int(a));
    throw SceneError("no animation '" + wanted + "' (the file has " + (known.empty() ? std::string("none") : known) + ")");
}

AnimationRange animation_range(const tinygltf::Model& model, int animation) {
    AnimationRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    const tinygltf::Animation& a = model.animations.at(size_t(animation));
    for (size_t s = 0; s < a.samplers.size(); ++s) {
        const std::vector<glm::vec4> times =
            read_vectors(model, a.samplers[s].input, "input of " + animation_name(model, animation), 1, 1, false);
        if (times.empty()) continue;
        range.start = std::min(range.start, double(times.front().x));
        range.end = std::max(range.end, double(times.back().x));
    }
    if (!(range.start <= range.end)) range = {0.0, 0.0};
    return range;
}

namespace {

// The property channel `c` animates: a KHR_animation_pointer pointer, or a node's TRS or weights.
PointerTarget resolve_channel(tinygltf::Model& model, const tinygltf::AnimationChannel& channel, const std::string& where) {
    std::string pointer;
    if (channel.target_path == "pointer") {
        const auto it = channel.target_extensions.find("KHR_animation_pointer");
        if (it == channel.target_extensions.end() || !it->second.IsObject() || !it->second.Has("pointer") ||
            !it->second.Get("pointer").IsString())
            throw SceneError(where + ": path 'pointer' without a KHR_animation_pointer pointer");
        pointer = it->second.Get("pointer").Get<std::string>();
    } else {
        if (size_t(channel.target_node) >= model.nodes.size())
            throw SceneError(where + ": target node " + std::to_string(channel.target_node) + " does not exist");
        if (channel.target_path != "translation" && channel.target_path != "rotation" &&
            channel.target_path != "scale" && channel.target_path != "weights")
            throw SceneError(where + ": unknown target path '" + channel.target_path + "'");
        pointer = "/nodes/" + std::to_string(channel.target_node) + "/" + channel.target_path;
    }
    try {
        PointerTarget target = resolve_animation_pointer(model, pointer);
        if (!target.set) target.ignored_why = where + ": pointer " + pointer + " is ignored: " + target.ignored_why;
        return target;
    } catch (const SceneError& e) {
        throw SceneError(where + ": " + e.what());
    }
}

}  // namespace

void pose_model(tinygltf::Model& model, int animation, double time, std::vector<std::string>* warnings) {
    if (animation < 0 || size_t(animation) >= model.animations.size()) return;
    const tinygltf::Animation& a = model.animations[size_t(animation)];
    for (size_t c = 0; c < a.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = a.channels[c];
        const std::string where = describe(model, animation, c);
        // No node and no pointer: the spec lets other extensions target something else.
        if (channel.target_node < 0 && channel.target_path != "pointer") continue;
        if (channel.sampler < 0 || size_t(channel.sampler) >= a.samplers.size())
            throw SceneError(where + ": sampler " + std::to_string(channel.sampler) + " does not exist");
        const PointerTarget target = resolve_channel(model, channel, where);
        if (!target.set) {
            if (warnings != nullptr && std::find(warnings->begin(), warnings->end(), target.ignored_why) == warnings->end())
                warnings->push_back(target.ignored_why);
            continue;
        }
        const Track track = read_track(model, a.samplers[size_t(channel.sampler)], target, where);
        target.set(sample(track, time, target.rotation));
    }
}

}  // namespace fh::gltf
