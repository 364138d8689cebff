// KHR_animation_pointer targets: JSON pointers into nodes, materials (with texture transforms and material
// extensions), KHR_lights_punctual lights and cameras, resolved to setters on the tinygltf::Model.
#include "scene/gltf/gltf_animation_pointer.h"

#include <tiny_gltf.h>

#include <map>

#include "scene/scene.h"

namespace fh::gltf {
namespace {

using Tokens = std::vector<std::string>;

// RFC 6901: "/a/b~1c" -> {"a", "b/c"}; "~0" is "~".
Tokens split_pointer(const std::string& pointer) {
    if (pointer.empty() || pointer[0] != '/') throw SceneError("pointer '" + pointer + "' does not start with '/'");
    Tokens tokens(1);
    for (size_t i = 1; i < pointer.size(); ++i) {
        const char c = pointer[i];
        if (c == '/') tokens.emplace_back();
        else if (c == '~' && i + 1 < pointer.size() && (pointer[i + 1] == '0' || pointer[i + 1] == '1'))
            tokens.back() += pointer[++i] == '0' ? '~' : '/';
        else if (c == '~') throw SceneError("pointer '" + pointer + "' has a '~' that is not ~0 or ~1");
        else tokens.back() += c;
    }
    return tokens;
}

// Token `t` as an index below `count`, naming `what` in the error.
size_t index_of(const std::string& t, size_t count, const char* what) {
    size_t index = 0;
    bool digits = !t.empty() && t.size() < 10;
    for (char c : t) {
        digits = digits && c >= '0' && c <= '9';
        if (digits) index = index * 10 + size_t(c - '0');
    }
    if (!digits || index >= count)
        throw SceneError(std::string(what) + " '" + t + "' does not exist (" + std::to_string(count) + " in the file)");
    return index;
}

// Whether tokens[first...] equal `path`.
bool tail_is(const Tokens& tokens, size_t first, std::initializer_list<const char*> path) {
    if (tokens.size() - first != path.size()) return false;
    size_t i = first;
    for (const char* p : path)
        if (tokens[i++] != p) return false;
    return true;
}

tinygltf::Value to_value(const std::vector<double>& v, bool boolean) {
    if (boolean) return tinygltf::Value(v[0] != 0.0);
    if (v.size() == 1) return tinygltf::Value(v[0]);
    tinygltf::Value::Array array;
    for (double x : v) array.emplace_back(x);
    return tinygltf::Value(std::move(array));
}

// Writes the value at tokens[first...] below the JSON object `object` (an extension map or an object Value), making
// the objects on the way.
void write_into(std::map<std::string, tinygltf::Value>& object, const Tokens& tokens, size_t first,
                const std::vector<double>& v, bool boolean) {
    std::map<std::string, tinygltf::Value>* current = &object;
    for (size_t i = first; i + 1 < tokens.size(); ++i) {
        tinygltf::Value& next = (*current)[tokens[i]];
        if (!next.IsObject()) next = tinygltf::Value(tinygltf::Value::Object{});
        current = &next.Get<tinygltf::Value::Object>();
    }
    (*current)[tokens.back()] = to_value(v, boolean);
}

// A target of `components` numbers set by `set`.
PointerTarget numbers(int components, std::function<void(const std::vector<double>&)> set) {
    PointerTarget t;
    t.components = components;
    t.set = std::move(set);
    return t;
}

PointerTarget ignored(std::string why) {
    PointerTarget t;
    t.ignored_why = std::move(why);
    return t;
}

PointerTarget generic(std::map<std::string, tinygltf::Value>& object, Tokens tokens, size_t first, bool boolean = false) {
    PointerTarget t;
    t.components = PointerTarget::FROM_ACCESSOR;
    t.boolean = boolean;
    t.set = [&object, tokens = std::move(tokens), first, boolean](const std::vector<double>& v) {
        write_into(object, tokens, first, v, boolean);
    };
    return t;
}

PointerTarget node_target(tinygltf::Model& model, const Tokens& tokens) {
    tinygltf::Node& node = model.nodes[index_of(tokens[1], model.nodes.size(), "node")];
    auto trs = [&](const char* what) {
        if (!node.matrix.empty())
            throw SceneError("animates the " + std::string(what) + " of node " + tokens[1] +
                             ", which has a matrix (the spec allows animating TRS nodes only)");
    };
    if (tail_is(tokens, 2, {"translation"})) {
        trs("translation");
        return numbers(3, [&node](const std::vector<double>& v) { node.translation = v; });
    }
    if (tail_is(tokens, 2, {"rotation"})) {
        trs("rotation");
        PointerTarget t = numbers(4, [&node](const std::vector<double>& v) { node.rotation = v; });
        t.rotation = true;
        return t;
    }
    if (tail_is(tokens, 2, {"scale"})) {
        trs("scale");
        return numbers(3, [&node](const std::vector<double>& v) { node.scale = v; });
    }
    if (tail_is(tokens, 2, {"weights"}))
        return numbers(PointerTarget::ANY, [&node](const std::vector<double>& v) { node.weights = v; });
    if (tail_is(tokens, 2, {"extensions", "KHR_node_visibility", "visible"})) {
        PointerTarget t = generic(node.extensions, tokens, 3, true);
        t.components = 1;
        return t;
    }
    return ignored("not a node property Fredholm renders");
}

// The core textureInfo of `material` that tokens[first...] start with, and how many tokens name it; nullptr if none.
tinygltf::ExtensionMap* core_texture_extensions(tinygltf::Material& m, const Tokens& tokens, size_t first,
                                                size_t& length) {
    // Each slot's path is one or two tokens (an array of std::initializer_list would dangle: its elements live only
    // as long as the expression that builds the array).
    struct Slot {
        const char* parent;  // nullptr for a slot at the material's top level
        const char* name;
        tinygltf::ExtensionMap* extensions;
    };
    auto& pbr = m.pbrMetallicRoughness;
    const Slot slots[] = {
        {"pbrMetallicRoughness", "baseColorTexture", &pbr.baseColorTexture.extensions},
        {"pbrMetallicRoughness", "metallicRoughnessTexture", &pbr.metallicRoughnessTexture.extensions},
        {nullptr, "normalTexture", &m.normalTexture.extensions},
        {nullptr, "emissiveTexture", &m.emissiveTexture.extensions},
    };
    for (const Slot& slot : slots) {
        const size_t path_length = slot.parent ? 2 : 1;
        if (tokens.size() < first + path_length + 3) continue;
        size_t i = first;
        if (slot.parent && tokens[i++] != slot.parent) continue;
        if (tokens[i] == slot.name && tokens[i + 1] == "extensions" && tokens[i + 2] == "KHR_texture_transform") {
            length = path_length;
            return slot.extensions;
        }
    }
    return nullptr;
}

PointerTarget material_target(tinygltf::Model& model, const Tokens& tokens) {
    tinygltf::Material& m = model.materials[index_of(tokens[1], model.materials.size(), "material")];
    auto& pbr = m.pbrMetallicRoughness;
    auto scalar = [](double& field) { return numbers(1, [&field](const std::vector<double>& v) { field = v[0]; }); };
    if (tail_is(tokens, 2, {"pbrMetallicRoughness", "baseColorFactor"}))
        return numbers(4, [&pbr](const std::vector<double>& v) { pbr.baseColorFactor = v; });
    if (tail_is(tokens, 2, {"pbrMetallicRoughness", "metallicFactor"})) return scalar(pbr.metallicFactor);
    if (tail_is(tokens, 2, {"pbrMetallicRoughness", "roughnessFactor"})) return scalar(pbr.roughnessFactor);
    if (tail_is(tokens, 2, {"emissiveFactor"}))
        return numbers(3, [&m](const std::vector<double>& v) { m.emissiveFactor = v; });
    if (tail_is(tokens, 2, {"alphaCutoff"})) return scalar(m.alphaCutoff);
    if (tail_is(tokens, 2, {"normalTexture", "scale"})) return scalar(m.normalTexture.scale);
    if (tokens.size() > 2 && tokens[2] == "occlusionTexture")
        return ignored("occlusionTexture is not read (a path tracer computes occlusion)");
    size_t length = 0;
    if (tinygltf::ExtensionMap* extensions = core_texture_extensions(m, tokens, 2, length))
        return generic(*extensions, tokens, 2 + length + 1);
    if (tokens.size() > 4 && tokens[2] == "extensions") {
        // The Object Model's pointers must name what the asset defines: the extension object at least.
        if (m.extensions.count(tokens[3]) == 0)
            throw SceneError("material " + tokens[1] + " has no " + tokens[3] + " for the pointer to animate");
        return generic(m.extensions, tokens, 3);
    }
    return ignored("not a material property Fredholm renders");
}

PointerTarget light_target(tinygltf::Model& model, const Tokens& tokens) {
    tinygltf::Light& light = model.lights[index_of(tokens[3], model.lights.size(), "light")];
    auto scalar = [](double& field) { return numbers(1, [&field](const std::vector<double>& v) { field = v[0]; }); };
    if (tail_is(tokens, 4, {"color"})) return numbers(3, [&light](const std::vector<double>& v) { light.color = v; });
    if (tail_is(tokens, 4, {"intensity"})) return scalar(light.intensity);
    if (tail_is(tokens, 4, {"spot", "innerConeAngle"})) return scalar(light.spot.innerConeAngle);
    if (tail_is(tokens, 4, {"spot", "outerConeAngle"})) return scalar(light.spot.outerConeAngle);
    if (tail_is(tokens, 4, {"range"})) return ignored("a light's range is not read (the inverse-square law holds)");
    return ignored("not a light property Fredholm renders");
}

PointerTarget camera_target(tinygltf::Model& model, const Tokens& tokens) {
    tinygltf::Camera& camera = model.cameras[index_of(tokens[1], model.cameras.size(), "camera")];
    if ((tokens[2] == "perspective" || tokens[2] == "orthographic") && tokens[2] != camera.type)
        throw SceneError("camera " + tokens[1] + " is " + camera.type + ", not " + tokens[2]);
    auto scalar = [](double& field) { return numbers(1, [&field](const std::vector<double>& v) { field = v[0]; }); };
    if (tail_is(tokens, 2, {"perspective", "yfov"})) return scalar(camera.perspective.yfov);
    if (tail_is(tokens, 2, {"perspective", "aspectRatio"})) return scalar(camera.perspective.aspectRatio);
    if (tail_is(tokens, 2, {"perspective", "znear"})) return scalar(camera.perspective.znear);
    if (tail_is(tokens, 2, {"perspective", "zfar"})) return scalar(camera.perspective.zfar);
    if (tail_is(tokens, 2, {"orthographic", "xmag"})) return scalar(camera.orthographic.xmag);
    if (tail_is(tokens, 2, {"orthographic", "ymag"})) return scalar(camera.orthographic.ymag);
    if (tail_is(tokens, 2, {"orthographic", "znear"})) return scalar(camera.orthographic.znear);
    if (tail_is(tokens, 2, {"orthographic", "zfar"})) return scalar(camera.orthographic.zfar);
    return ignored("not a camera property Fredholm renders");
}

}  // namespace

PointerTarget resolve_animation_pointer(tinygltf::Model& model, const std::string& pointer) {
    const Tokens tokens = split_pointer(pointer);
    if (tokens.size() >= 3 && tokens[0] == "nodes") return node_target(model, tokens);
    if (tokens.size() >= 3 && tokens[0] == "materials") return material_target(model, tokens);
    if (tokens.size() >= 5 && tokens[0] == "extensions" && tokens[1] == "KHR_lights_punctual" && tokens[2] == "lights")
        return light_target(model, tokens);
    if (tokens.size() >= 4 && tokens[0] == "cameras") return camera_target(model, tokens);
    return ignored("not a property Fredholm renders");
}

}  // namespace fh::gltf
