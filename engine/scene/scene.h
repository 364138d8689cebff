// The flattened scene: every glTF triangle in world space with its material, plus cameras and bounds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "shared/layout.h"

namespace fh {

// A problem with a scene file; the message reads "FILE: problem (where)".
struct SceneError : std::runtime_error {
    using runtime_error::runtime_error;
};

// A glTF camera placed by its node; the camera looks down its local -Z with +Y up.
struct SceneCamera {
    std::string name;
    glm::dmat4 world_from_camera{1.0};
    bool orthographic = false;
    double yfov = 0.0;             // radians, perspective only
    double xmag = 0.0, ymag = 0.0;  // half extents, orthographic only
};

struct Scene {
    std::filesystem::path source;
    std::vector<glm::vec3> positions;          // world space, 3 per triangle (flattened, non-indexed)
    std::vector<glm::vec3> normals;            // world space, 3 per triangle (zero where absent)
    std::vector<uint32_t> triangle_material;   // index into materials
    std::vector<uint8_t> triangle_has_normals; // 1: normals hold unit vertex normals; 0: flat shading
    std::vector<gpu::Material> materials;      // a default material appended if any primitive has none
    std::vector<SceneCamera> cameras;          // in scene-traversal order
    glm::dvec3 bounds_min{0.0}, bounds_max{0.0};
    std::vector<std::string> warnings;         // printed by the app

    size_t triangle_count() const { return positions.size() / 3; }
};

// Loads the default scene (or the first) of a .gltf (external or embedded buffers) or .glb file.
// Throws SceneError for a missing or malformed file, an unsupported required extension, or no triangles.
Scene load_gltf(const std::filesystem::path& file);

// A perspective camera (yfov 45 degrees) that frames the scene bounds, looking down -Z from the +Z side.
SceneCamera make_default_camera(const Scene& scene);

}  // namespace fh
