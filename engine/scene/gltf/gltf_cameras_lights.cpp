// The Flattener's cameras (with their motion over the shutter) and KHR_lights_punctual lights, placed by their nodes.
#include "scene/gltf/gltf_flattener.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"

namespace fh::gltf {
namespace {

// A camera node's motion from `open` to `close` (SceneCamera::moves): its origin along the line, its axes turned at
// a constant rate about one axis (the rotation between the two frames); world_from_camera becomes the pose halfway.
void set_camera_motion(SceneCamera& camera, const glm::dmat4& open, const glm::dmat4& close) {
    const glm::dmat3 r0(glm::normalize(glm::dvec3(open[0])), glm::normalize(glm::dvec3(open[1])),
                        glm::normalize(glm::dvec3(open[2])));
    const glm::dquat shorter = find_turn(open, close);
    const double angle = turn_angle(shorter);
    camera.moves = true;
    camera.motion_translation = glm::dvec3(close[3]) - glm::dvec3(open[3]);
    camera.motion_angle = angle;
    camera.motion_axis = angle > 0.0 ? glm::normalize(glm::dvec3(shorter.x, shorter.y, shorter.z)) : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dmat3 half = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.5 * angle, camera.motion_axis)) * r0;
    camera.world_from_camera = glm::dmat4(glm::dvec4(half[0], 0.0), glm::dvec4(half[1], 0.0), glm::dvec4(half[2], 0.0),
                                          glm::dvec4(0.5 * (glm::dvec3(open[3]) + glm::dvec3(close[3])), 1.0));
}

}  // namespace

void Flattener::add_camera(int camera_index, int node_index, const Placement& place) {
    const glm::dmat4& world = place.world;
    if (size_t(camera_index) >= model_.cameras.size())
        throw SceneError("camera " + std::to_string(camera_index) + " does not exist (" +
                         describe_node(model_, node_index) + ")");
    const tinygltf::Camera& source = model_.cameras[size_t(camera_index)];
    SceneCamera camera;
    camera.name = !source.name.empty() ? source.name : model_.nodes[size_t(node_index)].name;
    camera.world_from_camera = world;
    camera.orthographic = source.type == "orthographic";
    camera.yfov = source.perspective.yfov;
    camera.xmag = source.orthographic.xmag;
    camera.ymag = source.orthographic.ymag;
    if (place.moves()) set_camera_motion(camera, place.keys.front(), place.keys.back());
    scene_.cameras.push_back(camera);
}

// A KHR_lights_punctual reference on a node: {"light": index}.
void Flattener::add_light(const tinygltf::Value& extension, int node_index, const glm::dmat4& world) {
    const tinygltf::Value& index_value = gltf::json_member(extension, "light");
    if (!index_value.IsInt() && !index_value.IsNumber())
        throw SceneError(describe_node(model_, node_index) + ": KHR_lights_punctual has no light index");
    const double index = index_value.IsInt() ? double(index_value.Get<int>()) : index_value.Get<double>();
    if (!(index >= 0.0 && index < double(model_.lights.size())) || index != std::floor(index))
        throw SceneError(describe_node(model_, node_index) + ": KHR_lights_punctual light " +
                         (index == std::floor(index) && std::abs(index) < 1e15 ? std::to_string((long long)index)
                                                                             : std::to_string(index)) +
                         " does not exist (" + std::to_string(model_.lights.size()) +
                         " lights)");
    const tinygltf::Light& source = model_.lights[size_t(index)];
    const std::string where = "light " + std::to_string(size_t(index)) + " on " + describe_node(model_, node_index);
    SceneLight light;
    light.name = source.name;
    if (source.type == "point") light.type = gpu::LIGHT_POINT;
    else if (source.type == "spot") light.type = gpu::LIGHT_SPOT;
    else if (source.type == "directional") light.type = gpu::LIGHT_DIRECTIONAL;
    else throw SceneError(where + " has unknown type '" + source.type + "'");
    glm::dvec3 color(1.0);
    if (source.color.size() == 3) color = glm::dvec3(source.color[0], source.color[1], source.color[2]);
    const glm::dvec3 intensity = color * source.intensity;
    if (!(intensity.x >= 0.0 && intensity.y >= 0.0 && intensity.z >= 0.0) ||
        !std::isfinite(intensity.x + intensity.y + intensity.z) || std::max({intensity.x, intensity.y, intensity.z}) > 3.0e38)
        throw SceneError(where + " has a negative or non-finite color * intensity");
    light.intensity = glm::vec3(intensity);
    light.position = glm::dvec3(world[3]);
    const glm::dvec3 axis = -glm::dvec3(world[2]);  // the node's local -Z
    const double length = glm::length(axis);
    if (!(length > 0.0) || !std::isfinite(length))
        throw SceneError(where + ": the node's transform has no direction (zero or non-finite -Z axis)");
    light.direction = axis / length;
    if (light.type == gpu::LIGHT_SPOT) {
        light.inner_cone = float(source.spot.innerConeAngle);
        light.outer_cone = float(source.spot.outerConeAngle);
        if (!(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone &&
              light.outer_cone <= 0.5f * glm::pi<float>()))
            throw SceneError(where + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
    }
    if (source.range > 0.0) warn_once("KHR_lights_punctual range is ignored (lights follow the inverse-square law)");
    scene_.lights.push_back(light);
}

}  // namespace fh::gltf
