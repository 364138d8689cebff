// The viewer's camera controller: orbit, pan, zoom and fly around a target, starting from a scene camera.
#pragma once
#include <glm/glm.hpp>

#include "scene/scene.h"

namespace fh {

class ViewerCamera {
public:
    // `scene_radius` scales pan, fly and zoom steps.
    ViewerCamera(const SceneCamera& start, glm::dvec3 scene_center, double scene_radius);

    // Mouse motion in pixels over a window of height `window_height`.
    void orbit(double dx, double dy);
    void pan(double dx, double dy, double window_height);
    void zoom(double wheel_steps);
    // Moves eye and target together along the view axes, in units of the scene radius.
    void fly(double forward, double right, double up);
    void reset();

    // True until the first move since construction or reset: the camera is still the scene camera.
    bool unchanged() const { return unchanged_; }
    SceneCamera scene_camera() const;
    glm::dvec3 eye() const { return eye_; }
    glm::dvec3 target() const { return target_; }
    glm::dvec3 up() const { return up_; }
    double yfov_degrees() const;
    bool orthographic() const { return start_.orthographic; }

private:
    void set_from(const SceneCamera& camera);

    SceneCamera start_;
    glm::dvec3 scene_center_;
    double scene_radius_;
    glm::dvec3 eye_{0.0}, target_{0.0}, up_{0.0, 1.0, 0.0};
    double ymag_ = 1.0;  // orthographic half height
    bool unchanged_ = true;
};

// world_from_camera for a camera at `eye` looking at `target` (glTF: looks down -Z, +Y up).
glm::dmat4 look_at_camera(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up);

}  // namespace fh
