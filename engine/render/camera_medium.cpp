#include "render/camera_medium.h"

#include <glm/geometric.hpp>
#include <map>

namespace fh {

std::vector<gpu::RayItem> make_medium_probe_rays(glm::vec3 origin, uint32_t count) {
    static const float d = 0.57735027f;  // 1 / sqrt(3)
    static const glm::vec3 directions[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                           {0, 0, -1}, {d, d, d},  {-d, d, d},  {d, -d, d},  {d, d, -d},
                                           {-d, -d, d}, {-d, d, -d}, {d, -d, -d}, {-d, -d, -d}};
    std::vector<gpu::RayItem> rays;
    for (const glm::vec3& dir : directions) {
        if (rays.size() == count) break;
        rays.push_back({origin.x, origin.y, origin.z, 0u, dir.x, dir.y, dir.z, gpu::INVALID_INDEX});
    }
    return rays;
}

namespace {

glm::vec3 row_times(const glm::vec4& r0, const glm::vec4& r1, const glm::vec4& r2, const glm::vec3& v) {
    return {glm::dot(glm::vec3(r0), v), glm::dot(glm::vec3(r1), v), glm::dot(glm::vec3(r2), v)};
}

constexpr uint32_t ABSTAIN = gpu::INVALID_INDEX - 1u;

// The probe's vote by its first hit: the volume material whose back face it hits; INVALID_INDEX (outside) when it
// escapes; ABSTAIN when it hits anything else (an opaque or thin surface, the front of a volume), which says nothing
// about where the camera stands.
uint32_t medium_of_hit(const PackedScene& scene, const gpu::RayItem& ray, const gpu::HitItem& hit) {
    if (hit.triangle == gpu::INVALID_INDEX || hit.triangle >= scene.positions.size()) return gpu::INVALID_INDEX;
    const gpu::TrianglePositions& t = scene.positions[hit.triangle];
    glm::vec3 dir(ray.dir_x, ray.dir_y, ray.dir_z);
    uint32_t material = scene.shading[hit.triangle].material;
    if (hit.instance != gpu::INVALID_INDEX && hit.instance < scene.instances.size()) {
        const gpu::Instance& inst = scene.instances[hit.instance];
        dir = row_times(inst.object_from_render_0, inst.object_from_render_1, inst.object_from_render_2, dir);
        if (inst.material != gpu::INVALID_INDEX) material = inst.material;
    }
    const glm::vec3 p0(t.p0_x, t.p0_y, t.p0_z);
    const glm::vec3 ng = glm::cross(glm::vec3(t.p1_x, t.p1_y, t.p1_z) - p0, glm::vec3(t.p2_x, t.p2_y, t.p2_z) - p0);
    const bool back_face = glm::dot(ng, dir) > 0.0f;
    const bool volume = material < scene.material_layers.size() &&
                        (scene.material_layers[material].flags & gpu::LAYERS_VOLUME) != 0u;
    return back_face && volume ? material : ABSTAIN;
}

}  // namespace

uint32_t vote_camera_medium(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                            const std::vector<gpu::HitItem>& hits) {
    std::map<uint32_t, uint32_t> votes;
    for (size_t i = 0; i < probes.size() && i < hits.size(); ++i) ++votes[medium_of_hit(scene, probes[i], hits[i])];
    uint32_t best = gpu::INVALID_INDEX, best_votes = votes[gpu::INVALID_INDEX];
    for (const auto& [medium, n] : votes)
        if (medium != gpu::INVALID_INDEX && medium != ABSTAIN && n > best_votes) best = medium, best_votes = n;
    return best;
}

}  // namespace fh
