// Parses and applies the camera pose options; the look-at convention matches glTF (-Z forward, +Y up).
#include "app/cli/camera_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "app/view/viewer_camera.h"

namespace fh {
namespace {

glm::dvec3 to_vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

}  // namespace

void add_camera_pose_options(CLI::App& app, CameraPoseOptions& pose) {
    app.add_option("--look-from", pose.look_from, "camera position x,y,z (overrides --camera's pose)")
        ->delimiter(',')->expected(3);
    app.add_option("--look-at", pose.look_at, "point the camera looks at, x,y,z")->delimiter(',')->expected(3);
    app.add_option("--up", pose.up, "camera up direction x,y,z (default 0,1,0)")->delimiter(',')->expected(3);
    app.add_option("--yfov", pose.yfov_degrees, "vertical field of view in degrees (perspective cameras)")
        ->check(CLI::Range(0.01, 179.0));
}

SceneCamera apply_camera_pose(const SceneCamera& base, const CameraPoseOptions& pose) {
    SceneCamera camera = base;
    if (pose.yfov_degrees > 0) camera.yfov = pose.yfov_degrees * 3.14159265358979323846 / 180.0;
    if (pose.look_from.empty() && pose.look_at.empty() && pose.up.empty()) return camera;
    const glm::dmat4& m = base.world_from_camera;
    glm::dvec3 from = pose.look_from.empty() ? glm::dvec3(m[3]) : to_vec3(pose.look_from);
    glm::dvec3 at = pose.look_at.empty() ? from - glm::normalize(glm::dvec3(m[2])) : to_vec3(pose.look_at);
    glm::dvec3 up = pose.up.empty() ? glm::dvec3(0, 1, 0) : to_vec3(pose.up);
    if (!(glm::length(at - from) > 0)) throw std::invalid_argument("--look-from and --look-at are the same point");
    if (!(glm::length(glm::cross(glm::normalize(at - from), up)) > 1e-9))
        throw std::invalid_argument("--up is parallel to the viewing direction (or zero)");
    camera.name = "command line";
    camera.world_from_camera = look_at_camera(from, at, glm::normalize(up));
    camera.moves = false;  // a camera placed on the command line stands still
    return camera;
}

std::string format_camera_pose(const glm::dvec3& from, const glm::dvec3& at, const glm::dvec3& up, double yfov_degrees) {
    char text[256];
    std::snprintf(text, sizeof(text), "--look-from %.6g,%.6g,%.6g --look-at %.6g,%.6g,%.6g --up %.6g,%.6g,%.6g",
                  from.x, from.y, from.z, at.x, at.y, at.z, up.x, up.y, up.z);
    std::string options = text;
    if (yfov_degrees > 0) {  // orthographic cameras have none
        std::snprintf(text, sizeof(text), " --yfov %.6g", yfov_degrees);
        options += text;
    }
    return options;
}

}  // namespace fh
