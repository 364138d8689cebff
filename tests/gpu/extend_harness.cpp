// Drives one wavefront stage by hand: the queue counters and ray items are written by the test, not by
// generate, so the stage is checked in isolation.
#include "extend_harness.h"

#include <cstddef>
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#include "render/ray_tracer.h"
#include "scene/pack.h"
#include "scene/scene.h"
#include "vk/commands.h"
#include "../unit/scene/test_meshes.h"

namespace fh::test {
namespace {

Scene make_grey_scene(const std::vector<glm::vec3>& positions) {
    gpu::Material material{};
    material.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    material.roughness = 1.0f;
    material.ior = 1.5f;
    return make_single_material_scene(positions, material);
}

// Runs extend once over `rays`.
// Triangles are named as in the scene; the GPU's are in leaf order (TrianglePositions.source_index maps back).
ExtendResult run_extend_once(vk::Context& context, const PackedScene& packed, const std::vector<Ray>& rays,
                             bool sort_rays) {
    std::vector<uint32_t> leaf_index_of(packed.positions.size());
    for (size_t i = 0; i < packed.positions.size(); ++i) leaf_index_of[packed.positions[i].source_index] = uint32_t(i);
    std::vector<gpu::RayItem> items(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        const uint32_t from = rays[i].origin_triangle == gpu::INVALID_INDEX ? gpu::INVALID_INDEX
                                                                            : leaf_index_of[rays[i].origin_triangle];
        items[i] = {rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, uint32_t(i),
                    rays[i].dir.x,    rays[i].dir.y,    rays[i].dir.z,    from};
    }
    RayTracer tracer(context, packed, uint32_t(rays.size()), sort_rays);
    TracedRays traced = tracer.trace(items);
    ExtendResult result;
    result.hits = std::move(traced.hits);
    for (gpu::HitItem& hit : result.hits)
        if (hit.triangle != gpu::INVALID_INDEX) hit.triangle = packed.positions[hit.triangle].source_index;
    result.escaped_rays = traced.escaped_rays;
    EXPECT_EQ(context.validation_message_count(), 0u) << "Vulkan validation messages (printed above)";
    return result;
}

}  // namespace

vk::Context& shared_test_context() {
    static std::unique_ptr<vk::Context> context = [] {
        vk::ContextOptions options;
        const char* v = std::getenv("FREDHOLM_VALIDATION");
        options.validation = v && std::strcmp(v, "0") != 0;
        return std::make_unique<vk::Context>(options);
    }();
    return *context;
}

ExtendResult run_extend_stage(const std::vector<glm::vec3>& positions, const std::vector<Ray>& rays,
                              const BvhOptions& options, bool sort_rays) {
    vk::Context& context = shared_test_context();
    Scene scene = make_grey_scene(positions);
    PackedScene packed = pack_scene(scene, build_bvh(scene.positions, options));
    return run_extend_once(context, packed, rays, sort_rays);
}

std::vector<uint8_t> run_connect_stage(const std::vector<glm::vec3>& positions, const std::vector<ShadowRay>& rays) {
    vk::Context& context = shared_test_context();
    Scene scene = make_grey_scene(positions);
    PackedScene packed = pack_scene(scene, build_bvh(scene.positions, {}));
    std::vector<gpu::ShadowRayItem> items(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        gpu::ShadowRayItem& item = items[i];
        item.origin_x = rays[i].origin.x;
        item.origin_y = rays[i].origin.y;
        item.origin_z = rays[i].origin.z;
        item.dir_x = rays[i].dir.x;
        item.dir_y = rays[i].dir.y;
        item.dir_z = rays[i].dir.z;
        item.t_max = rays[i].t_max;
        item.origin_triangle = gpu::INVALID_INDEX;
    }
    RayTracer tracer(context, packed, uint32_t(rays.size()));
    TracedShadowRays traced = tracer.trace_shadow_rays(items);
    EXPECT_EQ(context.validation_message_count(), 0u) << "Vulkan validation messages (printed above)";
    return traced.occluded;
}

}  // namespace fh::test
