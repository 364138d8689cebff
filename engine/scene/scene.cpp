// Scene helpers that do not depend on the file format: the default camera, an instance's motion.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

namespace fh {

void check_render_range(const Scene& scene, const glm::dvec3& lo, const glm::dvec3& hi, const std::string& what) {
    const double reach = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y),
                                   std::abs(hi.z)});
    if (reach <= double(gpu::MAX_RENDER_COORDINATE)) return;
    char text[160];
    std::snprintf(text, sizeof(text), ": %s reaches %.3g units from the scene's centre, beyond the %.3g the renderer supports",
                  what.c_str(), reach, double(gpu::MAX_RENDER_COORDINATE));
    throw SceneError(scene.source.string() + text);
}

SceneCamera make_default_camera(const Scene& scene) {
    SceneCamera camera;
    camera.name = "default";
    camera.orthographic = false;
    camera.yfov = glm::radians(45.0);
    const glm::dvec3 center = 0.5 * (scene.bounds_min + scene.bounds_max);
    double radius = 0.5 * glm::length(scene.bounds_max - scene.bounds_min);
    if (!(radius > 0.0)) radius = 1.0;
    // Place the bounding sphere inside the vertical field of view: distance = radius / sin(yfov / 2).
    const double distance = radius / std::sin(0.5 * camera.yfov);
    camera.world_from_camera = glm::translate(glm::dmat4(1.0), center + glm::dvec3(0.0, 0.0, distance));
    camera.xmag = radius;
    camera.ymag = radius;
    return camera;
}

}  // namespace fh

namespace fh {

glm::dmat4 SceneInstance::render_from_object_at(double s) const {
    if (keys.empty()) return render_from_object;
    const double x = std::clamp(s, 0.0, 1.0) * double(keys.size() - 1);
    const size_t k = std::min(size_t(x), keys.size() - 2);
    const double f = x - double(k);
    return (1.0 - f) * keys[k] + f * keys[k + 1];
}

}  // namespace fh
