// Which volumes the camera stands in (KHR_materials_volume): a camera inside a closed glass or water mesh sees
// everything through that volume's absorption from its first segment on, so its paths start in that medium, and a
// camera in water inside a glass starts with both, the water innermost.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <vector>

#include "scene/pack.h"
#include "shared/layout.h"

namespace fh {

// The camera's volumes (material indices), innermost first, INVALID_INDEX past the last: at most three, the
// entries FrameParams holds (camera_medium, camera_medium_outer, camera_medium_outermost).
using CameraMedia = std::array<uint32_t, 3>;
inline constexpr CameraMedia NO_CAMERA_MEDIA{gpu::INVALID_INDEX, gpu::INVALID_INDEX, gpu::INVALID_INDEX};

// Rays from `origin` (render space) along the 6 axes and the 8 diagonals, at most `count` of them, leaving
// `origin_triangle` (a light's own triangle; INVALID_INDEX: none).
std::vector<gpu::RayItem> make_medium_probe_rays(glm::vec3 origin, uint32_t count,
                                                 uint32_t origin_triangle = gpu::INVALID_INDEX);

// Traces rays (the extend stage: closest hits, in order; origin_triangle is skipped as the stages skip it).
using TraceProbes = std::function<std::vector<gpu::HitItem>(const std::vector<gpu::RayItem>&)>;

// How many surfaces a probe crosses at most on its way out (volumes entered and left on the way count).
inline constexpr uint32_t MEDIUM_PROBE_STEPS = 8;

// The volumes the probes find the camera inside. Each probe walks out from the camera through the surfaces of
// volumes (materials with LAYERS_VOLUME), by their triangles' winding (geometric normal), as the shade stage does:
// a front face enters a volume along the way; a back face leaves it, or, if the probe did not enter it, is a volume
// the camera stands in (the first such is the innermost). A probe that escapes votes for the volumes it found
// (none: "outside"). One that meets any other surface (opaque, thin-walled, cut out), or is still walking after
// MEDIUM_PROBE_STEPS surfaces, votes for what it found so far, or abstains if that is nothing. The most votes win
// (the same volumes in the same order); a tie, or no vote at all, is "outside". At most three volumes are kept.
CameraMedia find_camera_media(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                              const TraceProbes& trace);

// The same for many points at once (each probe's `path` word names its point, 0 .. point_count - 1): one trace per
// step for all of them. The lights' volumes (render/light_media.h) are found so.
std::vector<CameraMedia> find_media_at_points(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                                              size_t point_count, const TraceProbes& trace);

}  // namespace fh
