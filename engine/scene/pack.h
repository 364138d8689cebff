// Packs a flattened Scene and its Bvh into the arrays the GPU stages read (layout.h), with the emitter table.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "scene/bvh/bvh.h"
#include "scene/bvh/scene_bvh.h"
#include "scene/effects.h"
#include "scene/light/environment.h"
#include "scene/scene.h"
#include "shared/layout.h"

namespace fh {

struct PackedScene {
    std::vector<gpu::BvhWideNode> nodes;            // the BVH as the GPU traverses it, root at 0 (scene_bvh.h)
    glm::vec3 bounds_lo{0.0f}, bounds_hi{0.0f};     // the scene's box (render space): SceneBvh's
    std::vector<gpu::Instance> instances;           // two-level BVH; empty: one level
    std::vector<gpu::TrianglePositions> positions;  // BVH leaf order
    std::vector<gpu::TriangleShading> shading;      // same order
    std::vector<gpu::Material> materials;
    std::vector<gpu::MaterialLayers> material_layers;  // one per material
    std::vector<gpu::Emitter> emitters;             // alias table over every light (may be empty)
    std::vector<double> emitter_power;              // the power of each entry's light (the alias table's weight)
    // --light-sampler (scene/light/light_sampler.h): the tree, when NEE uses it, over entries [0, light_tree_lights).
    std::vector<gpu::LightTreeNode> light_tree;
    uint32_t light_tree_lights = 0;
    uint32_t light_tree_depth = 0;
    double light_tree_build_seconds = 0.0;
    const char* light_sampler = "power";            // the one NEE uses: "tree", "power" or "uniform"
    std::vector<gpu::PunctualLight> punctual_lights;  // render space
    std::vector<gpu::TriangleAttributes> attributes;  // BVH leaf order; empty without textures and COLOR_0
    std::vector<gpu::TextureSlot> texture_slots;
    std::vector<gpu::TextureImage> texture_images;  // one per glTF image (width 0: not decoded, never read)
    std::vector<uint32_t> texels;                   // RGBA8 of every image, back to back
    EnvironmentMap environment;                     // empty: none
    float environment_pick_pdf = 0.0f;              // probability that NEE picks the environment
    SceneEffects effects;                           // what the stages are compiled for (scene/effects.h)
    double total_emitted_power = 0.0;               // watts if emission is in W / (m^2 sr)
    glm::dvec3 origin{0.0};                         // world position of the render-space origin (Scene::origin)
    uint32_t motion_segments = 1;                   // Scene::motion_segments
    // Emissive triangles of instances that move over the shutter: seen by rays that hit them, not in the light table.
    size_t moving_emitting_triangles = 0;
    std::string source;                             // Scene::source, for messages ("" when built in memory)
};

// scene.material_layers, one per material (a scene built without them, as in the tests, gets none).
std::vector<gpu::MaterialLayers> material_layers_of(const Scene& scene);

// Throws std::invalid_argument when `bvh` was not built over `scene`'s triangles. `environment` (may be empty)
// joins the lights NEE picks from, in proportion to its power over the scene's bounding disc.
PackedScene pack_scene(const Scene& scene, const SceneBvh& bvh, EnvironmentMap environment = {});
PackedScene pack_scene(const Scene& scene, const Bvh& bvh, EnvironmentMap environment = {});  // one level

// Mean luminance of a triangle's emissive texture times its emission factor (stratified over the triangle,
// nearest texels): the power NEE picks textured emitters by. 0: black everywhere the samples looked.
double mean_emitted_luminance(const Scene& scene, size_t triangle, const gpu::Material& material);

// Picks an entry of the emitter alias table for u in [0, 1), exactly as the GPU does: i = min(floor(u n),
// n - 1), u' = u n - i, keep i if u' < alias_threshold, else alias. Returns the entry index (its
// `triangle` is the picked triangle). `emitters` must not be empty.
uint32_t sample_alias(const std::vector<gpu::Emitter>& emitters, float u);

}  // namespace fh
