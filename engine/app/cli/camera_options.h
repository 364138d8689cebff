// Command-line camera pose options (--look-from, --look-at, --up, --yfov) shared by render and view.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace CLI {
class App;
}

namespace fh {

struct CameraPoseOptions {
    std::vector<double> look_from;  // x,y,z; empty = not given
    std::vector<double> look_at;
    std::vector<double> up;
    double yfov_degrees = 0;        // 0 = keep the base camera's
    bool given() const { return !look_from.empty() || !look_at.empty() || !up.empty() || yfov_degrees > 0; }
};

void add_camera_pose_options(CLI::App& app, CameraPoseOptions& pose);

// The base camera (from --camera or default framing) with any given pose option applied: --look-from and
// --look-at default to the base camera's position and a point one unit ahead of it, --up to +Y.
// Throws std::invalid_argument for a degenerate pose (look-from == look-at, or up parallel to the view).
SceneCamera apply_camera_pose(const SceneCamera& base, const CameraPoseOptions& pose);

// The options that reproduce a pose, e.g. "--look-from 0,1,3.5 --look-at 0,1,0 --up 0,1,0 --yfov 39.6".
std::string format_camera_pose(const glm::dvec3& from, const glm::dvec3& at, const glm::dvec3& up, double yfov_degrees);

}  // namespace fh
