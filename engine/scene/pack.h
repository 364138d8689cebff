// Packs a flattened Scene and its Bvh into the arrays the GPU stages read (layout.h), with the emitter table.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/bvh.h"
#include "scene/scene.h"
#include "shared/layout.h"

namespace fh {

struct PackedScene {
    std::vector<gpu::BvhNode> nodes;
    std::vector<gpu::TrianglePositions> positions;  // BVH leaf order
    std::vector<gpu::TriangleShading> shading;      // same order
    std::vector<gpu::Material> materials;
    std::vector<gpu::Emitter> emitters;             // alias table over emissive triangles (may be empty)
    double total_emitted_power = 0.0;               // watts if emission is in W / (m^2 sr)
};

// Throws std::invalid_argument when `bvh` was not built over `scene`'s triangles.
PackedScene pack_scene(const Scene& scene, const Bvh& bvh);

// Picks an entry of the emitter alias table for u in [0, 1), exactly as the GPU does: i = min(floor(u n),
// n - 1), u' = u n - i, keep i if u' < alias_threshold, else alias. Returns the entry index (its
// `triangle` is the picked triangle). `emitters` must not be empty.
uint32_t sample_alias(const std::vector<gpu::Emitter>& emitters, float u);

}  // namespace fh
