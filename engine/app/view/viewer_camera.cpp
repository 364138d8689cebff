// Orbit/pan/zoom/fly in double precision; the camera is kept as eye, target and up (roll-free after a move).
#include "app/view/viewer_camera.h"

#include <algorithm>
#include <cmath>

namespace fh {
namespace {
constexpr double ORBIT_RADIANS_PER_PIXEL = 0.005;
constexpr double ZOOM_PER_STEP = 0.85;  // distance factor per wheel step towards the target
}  // namespace

glm::dmat4 look_at_camera(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
    glm::dvec3 back = glm::normalize(eye - target);
    glm::dvec3 right = glm::cross(up, back);
    if (glm::length(right) < 1e-9) right = glm::cross(glm::abs(back.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0), back);
    right = glm::normalize(right);
    glm::dvec3 true_up = glm::cross(back, right);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(right, 0.0);
    m[1] = glm::dvec4(true_up, 0.0);
    m[2] = glm::dvec4(back, 0.0);
    m[3] = glm::dvec4(eye, 1.0);
    return m;
}

ViewerCamera::ViewerCamera(const SceneCamera& start, glm::dvec3 scene_center, double scene_radius)
    : start_(start), scene_center_(scene_center), scene_radius_(std::max(scene_radius, 1e-6)) {
    set_from(start);
}

void ViewerCamera::set_from(const SceneCamera& camera) {
    const glm::dmat4& m = camera.world_from_camera;
    eye_ = glm::dvec3(m[3]);
    glm::dvec3 forward = -glm::normalize(glm::dvec3(m[2]));
    up_ = glm::normalize(glm::dvec3(m[1]));
    // Orbit about the point straight ahead at the depth of the scene centre (or one radius if it is behind).
    double depth = glm::dot(scene_center_ - eye_, forward);
    if (depth < 1e-3 * scene_radius_) depth = scene_radius_;
    target_ = eye_ + forward * depth;
    ymag_ = camera.ymag > 0 ? camera.ymag : 1.0;
    unchanged_ = true;
}

void ViewerCamera::reset() { set_from(start_); }

void ViewerCamera::orbit(double dx, double dy) {
    glm::dvec3 offset = eye_ - target_;
    const double radius = glm::length(offset);
    // Yaw about the up axis, pitch about the right axis, keeping away from the poles.
    glm::dvec3 dir = offset / radius;
    const double yaw = -dx * ORBIT_RADIANS_PER_PIXEL;
    dir = dir * std::cos(yaw) + glm::cross(up_, dir) * std::sin(yaw) + up_ * glm::dot(up_, dir) * (1.0 - std::cos(yaw));
    const double elevation = std::asin(std::clamp(glm::dot(dir, up_), -1.0, 1.0));
    const double pitch = std::clamp(elevation + dy * ORBIT_RADIANS_PER_PIXEL, -1.5, 1.5) - elevation;
    glm::dvec3 right = glm::normalize(glm::cross(up_, dir));
    dir = dir * std::cos(pitch) + glm::cross(right, dir) * std::sin(pitch) * -1.0 +
          right * glm::dot(right, dir) * (1.0 - std::cos(pitch));
    eye_ = target_ + glm::normalize(dir) * radius;
    unchanged_ = false;
}

void ViewerCamera::pan(double dx, double dy, double window_height) {
    glm::dmat4 m = look_at_camera(eye_, target_, up_);
    // One pixel moves the target by one pixel's footprint at the target's depth.
    double half_height = start_.orthographic ? ymag_ : glm::length(eye_ - target_) * std::tan(0.5 * start_.yfov);
    double per_pixel = 2.0 * half_height / std::max(window_height, 1.0);
    glm::dvec3 move = (-dx * glm::dvec3(m[0]) + dy * glm::dvec3(m[1])) * per_pixel;
    eye_ += move;
    target_ += move;
    unchanged_ = false;
}

void ViewerCamera::zoom(double wheel_steps) {
    const double factor = std::pow(ZOOM_PER_STEP, wheel_steps);
    if (start_.orthographic) {
        ymag_ *= factor;
    } else {
        double distance = std::max(glm::length(eye_ - target_) * factor, 1e-4 * scene_radius_);
        eye_ = target_ + glm::normalize(eye_ - target_) * distance;
    }
    unchanged_ = false;
}

void ViewerCamera::fly(double forward, double right, double up) {
    glm::dmat4 m = look_at_camera(eye_, target_, up_);
    glm::dvec3 move = (-forward * glm::dvec3(m[2]) + right * glm::dvec3(m[0]) + up * up_) * scene_radius_;
    eye_ += move;
    target_ += move;
    unchanged_ = false;
}

SceneCamera ViewerCamera::scene_camera() const {
    if (unchanged_) return start_;
    SceneCamera camera = start_;
    camera.name = "viewer";
    camera.world_from_camera = look_at_camera(eye_, target_, up_);
    if (camera.orthographic) {
        camera.xmag = start_.ymag > 0 ? start_.xmag * ymag_ / start_.ymag : ymag_;
        camera.ymag = ymag_;
    }
    return camera;
}

double ViewerCamera::yfov_degrees() const { return start_.yfov * 180.0 / 3.14159265358979323846; }

}  // namespace fh
