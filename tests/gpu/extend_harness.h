// Runs the real `extend` stage on lavapipe over a hand-made ray queue and returns its hit records.
#pragma once
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bvh.h"
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

// One Vulkan context for the whole test binary (validation on when FREDHOLM_VALIDATION=1).
vk::Context& shared_test_context();

// Builds a BVH over `positions` (3 per triangle), queues `rays`, dispatches extend (after the ray sort with
// `sort_rays`, render/ray_sort.h), reads the hits.
ExtendResult run_extend_stage(const std::vector<glm::vec3>& positions, const std::vector<Ray>& rays,
                              const BvhOptions& options = {}, bool sort_rays = false);

}  // namespace fh::test
