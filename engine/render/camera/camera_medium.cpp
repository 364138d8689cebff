#include "render/camera/camera_medium.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <map>

namespace fh {

std::vector<gpu::RayItem> make_medium_probe_rays(glm::vec3 origin, uint32_t count, uint32_t origin_triangle) {
    static const float d = 0.57735027f;  // 1 / sqrt(3)
    static const glm::vec3 directions[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                           {0, 0, -1}, {d, d, d},  {-d, d, d},  {d, -d, d},  {d, d, -d},
                                           {-d, -d, d}, {-d, d, -d}, {d, -d, -d}, {-d, -d, -d}};
    std::vector<gpu::RayItem> rays;
    for (const glm::vec3& dir : directions) {
        if (rays.size() == count) break;
        rays.push_back({origin.x, origin.y, origin.z, 0u, dir.x, dir.y, dir.z, origin_triangle});
    }
    return rays;
}

namespace {

glm::vec3 row_times(const glm::vec4& r0, const glm::vec4& r1, const glm::vec4& r2, const glm::vec3& v) {
    return {glm::dot(glm::vec3(r0), v), glm::dot(glm::vec3(r1), v), glm::dot(glm::vec3(r2), v)};
}

// What a probe's hit is: not a volume's surface (NOT_A_VOLUME), or the volume's material and the side it is met from.
constexpr uint32_t NOT_A_VOLUME = gpu::INVALID_INDEX;
struct Crossing {
    uint32_t volume = NOT_A_VOLUME;
    bool back_face = false;
};

Crossing classify_hit(const PackedScene& scene, const gpu::RayItem& ray, const gpu::HitItem& hit) {
    if (hit.triangle >= scene.positions.size()) return {};
    const gpu::TrianglePositions& t = scene.positions[hit.triangle];
    glm::vec3 dir(ray.dir_x, ray.dir_y, ray.dir_z);
    uint32_t material = scene.shading[hit.triangle].material;
    if (hit.instance != gpu::INVALID_INDEX && hit.instance < scene.instances.size()) {
        const gpu::Instance& inst = scene.instances[hit.instance];
        dir = row_times(inst.object_from_render_0, inst.object_from_render_1, inst.object_from_render_2, dir);
        if (inst.material != gpu::INVALID_INDEX) material = inst.material;
    }
    const bool volume = material < scene.material_layers.size() &&
                        (scene.material_layers[material].flags & gpu::LAYERS_VOLUME) != 0u;
    if (!volume) return {};
    const glm::vec3 p0(t.p0_x, t.p0_y, t.p0_z);
    const glm::vec3 ng = glm::cross(glm::vec3(t.p1_x, t.p1_y, t.p1_z) - p0, glm::vec3(t.p2_x, t.p2_y, t.p2_z) - p0);
    return {material, glm::dot(ng, dir) > 0.0f};
}

// One probe on its way out.
struct Walk {
    std::vector<uint32_t> around;   // volumes left without being entered: the camera's, innermost first
    std::vector<uint32_t> entered;  // volumes entered on the way and not left yet
    bool abstains = false;
};

// Ends a walk on something that tells no more: it votes for what it found, or abstains if that is nothing.
void stop_walk(Walk& walk) { walk.abstains = walk.around.empty(); }

// Takes the hit of the walk's ray; returns true when the walk goes on past that surface.
bool step_walk(const PackedScene& scene, const gpu::RayItem& ray, const gpu::HitItem& hit, Walk& walk) {
    if (hit.triangle == gpu::INVALID_INDEX) return false;  // escaped: its vote is complete
    const Crossing c = classify_hit(scene, ray, hit);
    if (c.volume == NOT_A_VOLUME) {
        stop_walk(walk);
        return false;
    }
    if (!c.back_face) {
        walk.entered.push_back(c.volume);
    } else if (auto it = std::find(walk.entered.rbegin(), walk.entered.rend(), c.volume); it != walk.entered.rend()) {
        walk.entered.erase(std::next(it).base());  // leaves what it entered on the way
    } else {
        walk.around.push_back(c.volume);
        if (walk.around.size() == CameraMedia{}.size()) return false;  // all that FrameParams holds
    }
    return true;
}

gpu::RayItem continue_past(const gpu::RayItem& ray, const gpu::HitItem& hit) {
    gpu::RayItem next = ray;
    next.origin_x = ray.origin_x + hit.t * ray.dir_x;
    next.origin_y = ray.origin_y + hit.t * ray.dir_y;
    next.origin_z = ray.origin_z + hit.t * ray.dir_z;
    next.origin_triangle = hit.triangle;  // skipped, with its coplanar neighbours near t = 0 (traverse.glsl)
    return next;
}

CameraMedia count_votes(const std::vector<Walk>& walks) {
    std::map<std::vector<uint32_t>, uint32_t> votes;
    for (const Walk& walk : walks)
        if (!walk.abstains) ++votes[walk.around];
    const std::vector<uint32_t> outside;
    const std::vector<uint32_t>* best = &outside;
    uint32_t best_votes = votes[outside];
    for (const auto& [media, n] : votes)
        if (!media.empty() && n > best_votes) best = &media, best_votes = n;
    CameraMedia result = NO_CAMERA_MEDIA;
    std::copy_n(best->begin(), std::min(best->size(), result.size()), result.begin());
    return result;
}

}  // namespace

CameraMedia find_camera_media(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                              const TraceProbes& trace) {
    std::vector<gpu::RayItem> one_point = probes;
    for (gpu::RayItem& ray : one_point) ray.path = 0;
    return find_media_at_points(scene, one_point, 1, trace)[0];
}

std::vector<CameraMedia> find_media_at_points(const PackedScene& scene, const std::vector<gpu::RayItem>& probes,
                                              size_t point_count, const TraceProbes& trace) {
    std::vector<Walk> walks(probes.size());
    std::vector<gpu::RayItem> rays = probes;
    std::vector<size_t> walking(probes.size());
    for (size_t i = 0; i < walking.size(); ++i) walking[i] = i;
    const gpu::HitItem miss{0.0f, gpu::INVALID_INDEX, 0.0f, 0.0f, gpu::INVALID_INDEX};
    for (uint32_t step = 0; step < MEDIUM_PROBE_STEPS && !rays.empty(); ++step) {
        const std::vector<gpu::HitItem> hits = trace(rays);
        std::vector<gpu::RayItem> next_rays;
        std::vector<size_t> next_walking;
        for (size_t k = 0; k < rays.size(); ++k) {
            const gpu::HitItem& hit = k < hits.size() ? hits[k] : miss;
            if (step_walk(scene, rays[k], hit, walks[walking[k]])) {
                next_rays.push_back(continue_past(rays[k], hit));
                next_walking.push_back(walking[k]);
            }
        }
        rays = std::move(next_rays);
        walking = std::move(next_walking);
    }
    for (size_t index : walking) stop_walk(walks[index]);  // still walking after MEDIUM_PROBE_STEPS surfaces
    std::vector<std::vector<Walk>> by_point(point_count);
    for (size_t k = 0; k < probes.size(); ++k)
        if (probes[k].path < point_count) by_point[probes[k].path].push_back(walks[k]);
    std::vector<CameraMedia> media;
    media.reserve(point_count);
    for (const std::vector<Walk>& point_walks : by_point) media.push_back(count_votes(point_walks));
    return media;
}

}  // namespace fh
