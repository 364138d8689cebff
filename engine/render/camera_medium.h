// Which volume the camera stands in (KHR_materials_volume): a camera inside a closed glass or water mesh sees
// everything through that volume's absorption from its first segment on, so its paths start in that medium.
#pragma once
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "scene/pack.h"
#include "shared/layout.h"

namespace fh {

// Rays from `origin` (render space) along the 6 axes and the 8 diagonals, at most `count` of them.
std::vector<gpu::RayItem> make_medium_probe_rays(glm::vec3 origin, uint32_t count);

// The material whose volume the probes find the camera inside, else INVALID_INDEX. A probe that first hits the back
// face of a mesh whose material bounds a volume (LAYERS_VOLUME) votes for that material; one that escapes votes for
// "outside"; one that hits anything else (an opaque or thin surface, the front face of a volume) abstains. The most
// votes win; a tie, or no vote at all, is "outside". The back-face test uses the triangle's winding (geometric
// normal), as the shade stage does. Only the innermost volume is found (a camera in water in a glass starts in the
// water alone).
uint32_t vote_camera_medium(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                            const std::vector<gpu::HitItem>& hits);

}  // namespace fh
