// Runs the real `extend` stage (closest hit) or `connect` stage (any hit) on lavapipe over a hand-made ray queue and
// returns what it found.
#pragma once
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bvh/bvh.h"
#include "shared/layout.h"
#include "vk/context.h"

namespace fh::test {

struct Ray {
    glm::vec3 origin;
    glm::vec3 dir;
    uint32_t origin_triangle = gpu::INVALID_INDEX;  // the triangle (original index) the ray leaves, if any
};

struct ExtendResult {
    std::vector<gpu::HitItem> hits;     // triangle = original triangle index (INVALID_INDEX: miss)
    uint32_t escaped_rays = 0;          // as counted by the device
};

struct ShadowRay {
    glm::vec3 origin;
    glm::vec3 dir;
    float t_max;
};

// One Vulkan context for the whole test binary (validation on when FREDHOLM_VALIDATION=1).
vk::Context& shared_test_context();

// Builds a BVH over `positions` (3 per triangle), queues `rays`, dispatches extend (after the ray sort with
// `sort_rays`, render/ray_sort.h), reads the hits.
ExtendResult run_extend_stage(const std::vector<glm::vec3>& positions, const std::vector<Ray>& rays,
                              const BvhOptions& options = {}, bool sort_rays = false);

// Builds a BVH over `positions`, queues `rays` as shadow rays, dispatches connect, and returns per ray 1 where it found
// something between the origin and t_max (its path's radiance left at 0), else 0.
std::vector<uint8_t> run_connect_stage(const std::vector<glm::vec3>& positions, const std::vector<ShadowRay>& rays);

}  // namespace fh::test
