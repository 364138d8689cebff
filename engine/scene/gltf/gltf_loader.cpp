// load_gltf: walks the node hierarchy of a glTF 2.0 file and flattens every triangle into world space.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>
#include <stdexcept>

#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"
#include "scene/gltf/gltf_animation.h"
#include "scene/gltf/gltf_file.h"
#include "scene/gltf/gltf_flattener.h"
#include "scene/gltf/gltf_material.h"
#include "scene/gltf/gltf_texture.h"
#include "scene/thin_film_bound.h"
#include "scene/scene.h"

namespace fh {
namespace {

// The file reader (gltf_file.h) and the Flattener with its helpers (gltf_flattener.h).
using gltf::check_extensions;
using gltf::describe_node;
using gltf::find_turn;
using gltf::Flattener;
using gltf::local_transform;
using gltf::MAX_NODE_INSTANCES;
using gltf::read_model;
using gltf::turn_angle;

// The root nodes to draw: the default scene, else the first; without scenes, every node no one parents.
std::vector<int> find_root_nodes(const tinygltf::Model& model, std::vector<std::string>& warnings) {
    if (!model.scenes.empty()) {
        const int index = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (size_t(index) >= model.scenes.size())
            throw SceneError("default scene " + std::to_string(index) + " does not exist");
        return model.scenes[size_t(index)].nodes;
    }
    warnings.push_back("the file defines no scene: drawing every root node");
    std::vector<uint8_t> is_child(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < is_child.size()) is_child[size_t(child)] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < model.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(int(i));
    // Finite trees always have a root; without one, "no triangles" would hide the real problem.
    if (roots.empty() && !model.nodes.empty())
        throw SceneError("every node is the child of another: the node hierarchy is a cycle "
                         "(and no scene lists roots)");
    return roots;
}

// glTF nodes must form disjoint trees; a node listed as the child of several nodes is drawn once per parent.
void warn_about_shared_nodes(const tinygltf::Model& model, std::vector<std::string>& warnings) {
    std::vector<uint32_t> parents(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < parents.size()) ++parents[size_t(child)];
    size_t shared = 0;
    int first = -1;
    for (size_t i = 0; i < parents.size(); ++i)
        if (parents[i] > 1 && shared++ == 0) first = int(i);
    if (shared > 0)
        warnings.push_back(std::to_string(shared) + " node(s) have several parents (first: " +
                           describe_node(model, first) + "): drawn once per parent, although glTF requires a tree");
}

// The walk visits a node once per path from a root, so shared children multiply: a 600-byte file of 40 nodes
// that each list the next twice took seconds to reach MAX_NODE_INSTANCES (a fuzzer timeout under ASan).
// Counting paths in topological order (Kahn) costs O(nodes + children) and refuses such files at once. Nodes on
// or below a cycle are not counted: the walk reports the cycle, or stops at the limit itself.
void check_node_instances(const tinygltf::Model& model, const std::vector<int>& roots) {
    const size_t n = model.nodes.size();
    std::vector<size_t> parents(n, 0), paths(n, 0);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && size_t(child) < n) ++parents[size_t(child)];
    for (int root : roots)
        if (root >= 0 && size_t(root) < n) ++paths[size_t(root)];
    std::vector<size_t> ready;
    for (size_t i = 0; i < n; ++i)
        if (parents[i] == 0) ready.push_back(i);
    size_t instances = 0;
    while (!ready.empty()) {
        const size_t i = ready.back();
        ready.pop_back();
        instances += paths[i];  // each term is at most MAX_NODE_INSTANCES: no overflow before the check
        if (instances > MAX_NODE_INSTANCES)
            throw SceneError("the node hierarchy has more than " + std::to_string(MAX_NODE_INSTANCES) +
                             " node instances (nodes shared by several parents multiply; at " +
                             describe_node(model, int(i)) + ")");
        for (int child : model.nodes[i].children) {
            if (child < 0 || size_t(child) >= n) continue;
            paths[size_t(child)] = std::min(paths[size_t(child)] + paths[i], MAX_NODE_INSTANCES + 1);
            if (--parents[size_t(child)] == 0) ready.push_back(size_t(child));
        }
    }
}

// KHR_materials_variants: the names the file defines, and the index of `wanted` among them (-1 for "").
int choose_variant(const tinygltf::Model& model, const std::string& wanted, std::vector<std::string>& names) {
    const auto it = model.extensions.find("KHR_materials_variants");
    if (it != model.extensions.end() && it->second.IsObject() && it->second.Has("variants")) {
        const tinygltf::Value& variants = it->second.Get("variants");
        for (size_t v = 0; variants.IsArray() && v < variants.ArrayLen(); ++v) {
            const tinygltf::Value& name = gltf::json_member(variants.Get(int(v)), "name");
            names.push_back(name.IsString() ? name.Get<std::string>() : "variant " + std::to_string(v));
        }
    }
    if (wanted.empty()) return -1;
    for (size_t v = 0; v < names.size(); ++v)
        if (names[v] == wanted) return int(v);
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + ("'" + n + "'");
    throw SceneError("no material variant '" + wanted + "' (KHR_materials_variants; the file has " +
                     (known.empty() ? std::string("none") : known) + ")");
}

// Motion blur: every node's local transform at the ends of K equal parts of the shutter (locals[k][node]), K doubled
// from 1 until no node turns more than MAX_TURN_PER_MOTION_SEGMENT between two keys, at most MAX_MOTION_SEGMENTS.
// Returns the largest turn between two keys (radians). The model's nodes are restored.
double key_shutter(tinygltf::Model& model, int animation, const LoadOptions& options,
                   std::vector<std::vector<glm::dmat4>>& locals) {
    const std::vector<tinygltf::Node> still = model.nodes;
    for (uint32_t segments = 1;; segments *= 2) {
        locals.assign(segments + 1, {});
        for (uint32_t k = 0; k <= segments; ++k) {
            const double s = double(k) / segments;
            gltf::pose_model(model, animation, options.time + (1.0 - s) * options.shutter_open + s * options.shutter_close);
            for (const tinygltf::Node& node : model.nodes) locals[k].push_back(local_transform(node));
            model.nodes = still;
        }
        double turn = 0.0;
        for (uint32_t k = 0; k < segments; ++k)
            for (size_t n = 0; n < model.nodes.size(); ++n)
                if (locals[k][n] != locals[k + 1][n]) {
                    const double a = turn_angle(find_turn(locals[k][n], locals[k + 1][n]));
                    if (std::isfinite(a)) turn = std::max(turn, a);
                }
        if (turn <= MAX_TURN_PER_MOTION_SEGMENT || segments >= MAX_MOTION_SEGMENTS) return turn;
    }
}

Scene load_unprefixed(const std::filesystem::path& file, const LoadOptions& options) {
    Scene scene;
    scene.source = file;
    tinygltf::Model model = read_model(file, scene.warnings, options.memory_limit);
    check_extensions(model, scene.warnings);
    std::vector<std::vector<glm::dmat4>> local_keys;  // motion blur: every node's transform at the shutter's keys
    if (options.animate || (options.has_shutter() && !model.animations.empty())) {
        const int animation = gltf::choose_animation(model, options.animation);
        if (animation < 0) throw SceneError("--time: the file has no animations");
        scene.animation = gltf::animation_name(model, animation);
        const gltf::AnimationRange range = gltf::animation_range(model, animation);
        scene.animation_start = range.start;
        scene.animation_end = range.end;
        if (options.has_shutter()) {
            const double turn = key_shutter(model, animation, options, local_keys);
            scene.motion_segments = uint32_t(local_keys.size() - 1);
            if (turn > MAX_TURN_PER_MOTION_SEGMENT) {
                char text[256];
                std::snprintf(text, sizeof text,
                              "a node turns by %.0f degrees in one of %u motion segments of the shutter: motion blur "
                              "follows its chord, which shrinks the mesh by up to %.1f%% there (a shorter shutter "
                              "shrinks less)",
                              glm::degrees(turn), scene.motion_segments, 100.0 * (1.0 - std::cos(0.5 * turn)));
                scene.warnings.push_back(text);
            }
        }
        // Last, at the shutter's centre: what is not a node transform (materials, lights, a camera's field of view,
        // visibility) holds this value over the shutter.
        gltf::pose_model(model, animation, options.time + 0.5 * (options.shutter_open + options.shutter_close),
                         &scene.warnings);
    }
    for (size_t a = 0; a < model.animations.size(); ++a) scene.animations.push_back(gltf::animation_name(model, int(a)));
    scene.images = gltf::take_images(model);
    for (size_t m = 0; m < model.materials.size(); ++m) {
        scene.materials.push_back(gltf::convert_material(model, int(m), scene));
        scene.material_layers.push_back(gltf::convert_material_layers(model, int(m), scene));
        const FilmFresnelBound bound = bound_thin_film_fresnel(scene.materials.back(), scene.material_layers.back());
        scene.material_layers.back().iridescence_albedo_f0 = bound.a;
        scene.material_layers.back().iridescence_albedo_f90 = bound.b;
    }

    warn_about_shared_nodes(model, scene.warnings);
    Flattener flattener(model, scene, choose_variant(model, options.variant, scene.variants));
    flattener.set_generate_tangents(options.mikktspace_tangents);
    const std::vector<int> roots = find_root_nodes(model, scene.warnings);
    check_node_instances(model, roots);
    flattener.compute_node_worlds(roots);
    const std::vector<glm::dmat4> root_keys(local_keys.size(), glm::dmat4(1.0));
    flattener.set_shutter_transforms(std::move(local_keys));
    for (int root : roots) flattener.visit_node(root, glm::dmat4(1.0), 0, root_keys);
    flattener.finish(options.rebase, options.instancing);
    if (scene.triangle_count() == 0) throw SceneError("no triangles in the scene");
    return scene;
}

}  // namespace

Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options) {
    try {
        return load_unprefixed(file, options);
    } catch (const SceneError& e) {
        throw SceneError(file.string() + ": " + e.what());
    } catch (const std::bad_alloc&) {
        throw SceneError(file.string() + ": out of memory while loading the scene");
    } catch (const std::exception& e) {  // from tinygltf or the standard library: still name the file
        throw SceneError(file.string() + ": " + e.what());
    }
}

}  // namespace fh
