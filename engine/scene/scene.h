// The flattened scene: every glTF triangle in world space with its material, plus cameras and bounds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/instancing.h"
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
    // Thin lens (glTF has none: set from the command line, app/lens_options.h). A radius of 0 is the pinhole.
    double aperture_radius = 0.0;   // world units
    double focus_distance = 1.0;    // world units, along the view direction: the plane in focus
    uint32_t aperture_blades = 0;   // 0: a disk; 3 or more: a regular polygon
    double aperture_rotation = 0.0; // radians, the polygon's turn about the view direction
    bool has_lens() const { return aperture_radius > 0.0; }
    // Motion blur (LoadOptions shutter): a camera whose node moves during the shutter. world_from_camera is then where
    // it stands halfway, and over the shutter its origin moves by motion_translation (world) and its axes turn by
    // motion_angle radians about the unit motion_axis (world), open to close, at a constant rate.
    bool moves = false;
    glm::dvec3 motion_translation{0.0};
    glm::dvec3 motion_axis{0.0, 0.0, 1.0};
    double motion_angle = 0.0;
};

// A KHR_lights_punctual light placed by its node (world space; it shines down its node's local -Z).
struct SceneLight {
    std::string name;
    uint32_t type = gpu::LIGHT_POINT;  // gpu::LIGHT_POINT / LIGHT_SPOT / LIGHT_DIRECTIONAL
    glm::dvec3 position{0.0};          // world
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit, the way the light travels
    glm::vec3 intensity{1.0f};         // color * intensity (candela or lux, taken as the scene's units)
    float inner_cone = 0.0f;           // spot: radians
    float outer_cone = 0.7853982f;
};

// A decoded texture image (scene/gltf/image_decode.h); the GPU reads its texels as they are.
struct SceneImage {
    std::string name;     // "image N 'name'" for messages
    uint32_t width = 0, height = 0;
    std::vector<uint32_t> texels;  // RGBA8, r in the low byte; empty: could not be decoded (KTX2), never read
};

// A mesh stored once, in its object space, for a two-level BVH: triangles [first_triangle, + triangle_count)
// of the Scene arrays.
struct SceneMesh {
    size_t first_triangle = 0;
    size_t triangle_count = 0;
};

// One placement of a SceneMesh (a node that draws it, or one EXT_mesh_gpu_instancing element).
struct SceneInstance {
    uint32_t mesh = 0;
    glm::dmat4 render_from_object{1.0};  // world transform with the render-space origin subtracted
    uint32_t material = gpu::INVALID_INDEX;  // replaces the mesh's material (glTF meshes that share geometry)
    // Motion blur: an instance whose node moves during the shutter has its transforms at shutter times k / K, k = 0..K
    // (K = Scene::motion_segments), and moves linearly between them (shaders/lib/geometry/motion.glsl); render_from_object is
    // then where that path has it at the shutter's centre.
    std::vector<glm::dmat4> keys;  // empty: it stands still
    bool moves() const { return !keys.empty(); }
    glm::dmat4 render_from_object_at(double s) const;  // s in [0, 1]
};

inline constexpr double MAX_TURN_PER_MOTION_SEGMENT = 0.0872664626;  // radians: 5 degrees (0.1% chord shrink)
inline constexpr uint32_t MAX_MOTION_SEGMENTS = 64;

struct LoadOptions {
    // Render-space origin at the centre of the scene bounds: world positions are composed in double and the
    // origin subtracted before rounding to float, so a scene far from the world origin keeps the precision
    // it has near it (off: render space = world space, only to show what that costs).
    bool rebase = true;
    // KHR_materials_variants: the variant whose materials primitives use (empty: the file's default materials).
    std::string variant;
    Instancing instancing = Instancing::automatic;  // scene/instancing.h
    // Without TANGENT: MikkTSpace tangents where a material needs a tangent frame (gltf_tangents.h); off: none, and the
    // shader derives each triangle's frame from its texture coordinates (to compare with).
    bool mikktspace_tangents = true;
    // glTF animation: with `animate`, the scene is posed at `time` seconds by the animation `animation` names ("": the
    // first; an index or a name). Without it the nodes keep the file's transforms and weights.
    bool animate = false;
    std::string animation;
    double time = 0.0;
    // Motion blur: the shutter, seconds relative to `time` (open < close; equal: none). With one, the scene is posed by
    // the animation even without `animate` (at `time`; nothing moves in a file without animations): nodes that move
    // between open and close become instances that move linearly over it, and the camera moves with its node.
    // Deforming meshes (skins, morph targets) and punctual lights stand where they are at the shutter's centre.
    // Instances are keyed at the ends of Scene::motion_segments equal parts of the shutter: doubled from 1 until no
    // node's transform turns more than MAX_TURN_PER_MOTION_SEGMENT in one part, at most MAX_MOTION_SEGMENTS.
    double shutter_open = 0.0, shutter_close = 0.0;
    bool has_shutter() const { return shutter_close > shutter_open; }
    // Bytes the file's buffers and decoded textures may take (scene/memory_limit.h); 0: no limit. Textures are
    // decoded only after their declared sizes fit.
    uint64_t memory_limit = 0;
};

struct Scene {
    std::filesystem::path source;
    glm::dvec3 origin{0.0};                    // world position of the render-space origin (LoadOptions::rebase)
    std::vector<glm::vec3> positions;          // render space (world - origin), 3 per triangle (non-indexed)
    std::vector<glm::vec3> normals;            // world directions, 3 per triangle (zero where absent)
    std::vector<uint32_t> triangle_material;   // index into materials
    std::vector<uint8_t> triangle_has_normals; // 1: normals hold unit vertex normals; 0: flat shading
    std::vector<gpu::Material> materials;      // a default material appended if any primitive has none
    std::vector<gpu::MaterialLayers> material_layers;  // the KHR material extensions, parallel to materials
    std::vector<gpu::TextureSlot> texture_slots;  // what Material.*_texture index
    std::vector<SceneImage> images;            // glTF images in file order
    // Vertex attributes, 3 per triangle like positions; empty unless the file has textures or COLOR_0.
    std::vector<glm::vec2> texcoords0, texcoords1;  // (0, 0) where the primitive has none
    std::vector<glm::vec4> colors;             // COLOR_0 (1, 1, 1, 1 where absent)
    std::vector<glm::vec4> tangents;           // world xyz, w = bitangent sign; (0, 0, 0, 0) where absent
    std::vector<SceneCamera> cameras;          // in scene-traversal order, world space
    std::vector<SceneLight> lights;            // punctual lights, world space
    glm::dvec3 bounds_min{0.0}, bounds_max{0.0};  // world space, of the triangles
    std::vector<std::string> variants;         // KHR_materials_variants names, in file order
    std::vector<std::string> animations;       // "animation N 'name'", in file order
    std::string animation;                     // the one posed (LoadOptions::animate), else empty
    double animation_start = 0.0, animation_end = 0.0;  // its first and last keyframe times, seconds
    size_t moving_instances = 0;               // instances that move during the shutter (SceneInstance::moves)
    uint32_t motion_segments = 1;              // equal parts of the shutter between motion keys (SceneInstance::keys)
    // Triangles of each primitive's geometry (POSITION and index accessors) counted once however many nodes or
    // meshes draw it; the flattened arrays hold every copy.
    size_t unique_triangle_count = 0;
    // Two-level scenes: triangles [0, world_triangle_count) are in render space, the rest belong to `meshes`
    // (object space) and are drawn once per instance. Without instances every triangle is in render space.
    size_t world_triangle_count = 0;
    std::vector<SceneMesh> meshes;
    std::vector<SceneInstance> instances;
    std::vector<std::string> warnings;         // printed by the app

    size_t triangle_count() const { return positions.size() / 3; }  // stored (each instanced mesh once)
    size_t rendered_triangle_count() const {                         // every instance's triangles
        size_t n = instances.empty() ? triangle_count() : world_triangle_count;
        for (const SceneInstance& i : instances) n += meshes[i.mesh].triangle_count;
        return n;
    }
};

// Loads the default scene (or the first) of a .gltf (external or embedded buffers) or .glb file.
// Throws SceneError for a missing or malformed file, an unsupported required extension, or no triangles.
// Triangles with NaN/Inf positions or no area in float are dropped (counted in a warning).
Scene load_gltf(const std::filesystem::path& file, const LoadOptions& options = {});

// A perspective camera (yfov 45 degrees) that frames the scene bounds, looking down -Z from the +Z side.
SceneCamera make_default_camera(const Scene& scene);

// Throws SceneError (naming the scene's file) when the render-space box [lo, hi] of `what` ("the geometry", "the
// camera") reaches beyond gpu::MAX_RENDER_COORDINATE along an axis: the GPU's box tests hold only within it
// (intersect.glsl make_safe_inverse_dir).
void check_render_range(const Scene& scene, const glm::dvec3& lo, const glm::dvec3& hi, const std::string& what);

}  // namespace fh
