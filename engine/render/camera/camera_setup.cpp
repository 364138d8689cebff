// Camera basis vectors in world space, computed in double precision from the node transform.
#include "render/camera/camera_setup.h"

#include <cmath>
#include <string>

namespace fh {

void set_frame_camera(gpu::FrameParams& frame, const SceneCamera& camera, uint32_t width, uint32_t height,
                      const glm::dvec3& render_origin) {
    const glm::dmat4& m = camera.world_from_camera;
    glm::dvec3 origin = glm::dvec3(m[3]) - render_origin;  // in double, then rounded: render space
    // glTF cameras look down -Z with +Y up; columns of the matrix are the camera axes in world space.
    glm::dvec3 right = glm::normalize(glm::dvec3(m[0]));
    glm::dvec3 up = glm::normalize(glm::dvec3(m[1]));
    glm::dvec3 forward = -glm::normalize(glm::dvec3(m[2]));
    double aspect = double(width) / double(height);
    double half_h = camera.orthographic ? camera.ymag : std::tan(0.5 * camera.yfov);
    double half_w = half_h * aspect;
    frame.camera_origin = glm::vec4(glm::vec3(origin), 0.0f);
    frame.camera_right = glm::vec4(glm::vec3(right * half_w), 0.0f);
    frame.camera_up = glm::vec4(glm::vec3(up * half_h), 0.0f);
    frame.camera_forward = glm::vec4(glm::vec3(forward), 0.0f);
    frame.camera_type = camera.orthographic ? gpu::CAMERA_ORTHOGRAPHIC : gpu::CAMERA_PERSPECTIVE;
    frame.lens_radius = float(camera.aperture_radius);
    frame.focus_distance = float(camera.focus_distance);
    frame.aperture_blades = camera.aperture_blades;
    frame.aperture_rotation = float(camera.aperture_rotation);
    frame.camera_motion_translation = glm::vec4(0.0f);
    frame.camera_motion_rotation = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);
    if (camera.moves) {  // lib/geometry/camera.glsl
        frame.camera_motion_translation = glm::vec4(glm::vec3(camera.motion_translation), 0.0f);
        frame.camera_motion_rotation = glm::vec4(glm::vec3(camera.motion_axis), float(camera.motion_angle));
    }
}

namespace {

SceneCamera check_camera_range(const Scene& scene, const SceneCamera& camera) {
    const glm::dvec3 at = glm::dvec3(camera.world_from_camera[3]) - scene.origin;
    check_render_range(scene, at, at, "the camera");
    return camera;
}

}  // namespace

SceneCamera choose_camera(const Scene& scene, int index) {
    if (index < 0) return check_camera_range(scene, scene.cameras.empty() ? make_default_camera(scene) : scene.cameras.front());
    if (size_t(index) >= scene.cameras.size())
        throw SceneError(scene.source.string() + ": camera " + std::to_string(index) + " requested, but the scene has " +
                         std::to_string(scene.cameras.size()) + " camera(s)");
    return check_camera_range(scene, scene.cameras[size_t(index)]);
}

}  // namespace fh
