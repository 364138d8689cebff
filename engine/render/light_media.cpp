#include "render/light_media.h"

#include <map>

namespace fh {

namespace {

// Where entry e's light is probed from, and the triangle its probes leave; false for a light at infinity.
bool find_probe_origin(const PackedScene& scene, const gpu::Emitter& e, glm::vec3& origin, uint32_t& triangle) {
    triangle = gpu::INVALID_INDEX;
    if (e.light == gpu::ENVIRONMENT_LIGHT) return false;
    if (e.light & gpu::PUNCTUAL_LIGHT_BIT) {
        const gpu::PunctualLight& light = scene.punctual_lights[e.light & ~gpu::PUNCTUAL_LIGHT_BIT];
        if (light.type == gpu::LIGHT_DIRECTIONAL) return false;
        origin = glm::vec3(light.position);
        return true;
    }
    const gpu::TrianglePositions& t = scene.positions[e.light];
    origin = (glm::vec3(t.p0_x, t.p0_y, t.p0_z) + glm::vec3(t.p1_x, t.p1_y, t.p1_z) + glm::vec3(t.p2_x, t.p2_y, t.p2_z)) /
             3.0f;
    triangle = e.light;
    return true;
}

// The key of the light whose answer entry e takes: itself, or past MAX_PROBED_LIGHTS its material's first triangle.
uint64_t probe_key(const PackedScene& scene, const gpu::Emitter& e, bool by_material) {
    const bool triangle = e.light != gpu::ENVIRONMENT_LIGHT && !(e.light & gpu::PUNCTUAL_LIGHT_BIT);
    if (!by_material || !triangle) return e.light;
    return (uint64_t(1) << 32) | scene.shading[e.light].material;
}

}  // namespace

std::vector<gpu::uvec4> find_light_media(const PackedScene& scene, const TraceProbes& trace) {
    const bool by_material = scene.emitters.size() > MAX_PROBED_LIGHTS;
    std::map<uint64_t, uint32_t> point_of_key;  // probe key -> probed point
    std::vector<uint32_t> point_of_entry(scene.emitters.size(), gpu::INVALID_INDEX);
    std::vector<gpu::RayItem> probes;
    for (size_t k = 0; k < scene.emitters.size(); ++k) {
        glm::vec3 origin;
        uint32_t triangle;
        if (!find_probe_origin(scene, scene.emitters[k], origin, triangle)) continue;
        const auto [it, added] =
            point_of_key.emplace(probe_key(scene, scene.emitters[k], by_material), uint32_t(point_of_key.size()));
        point_of_entry[k] = it->second;
        if (!added) continue;
        for (gpu::RayItem ray : make_medium_probe_rays(origin, LIGHT_PROBE_RAYS, triangle)) {
            ray.path = it->second;
            probes.push_back(ray);
        }
    }
    const std::vector<CameraMedia> media = find_media_at_points(scene, probes, point_of_key.size(), trace);
    std::vector<gpu::uvec4> result(std::max<size_t>(scene.emitters.size(), 1), gpu::uvec4(gpu::INVALID_INDEX));
    for (size_t k = 0; k < scene.emitters.size(); ++k)
        if (point_of_entry[k] != gpu::INVALID_INDEX) {
            const CameraMedia& m = media[point_of_entry[k]];
            result[k] = gpu::uvec4(m[0], m[1], m[2], gpu::INVALID_INDEX);
        }
    return result;
}

}  // namespace fh
