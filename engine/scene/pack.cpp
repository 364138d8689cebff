// Packs triangles in BVH leaf order and builds the emitter alias table (Walker 1977; Vose 1991).
#include "scene/pack.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/packing.hpp>

#include "lib/core/cpp_compat.h"
#include "scene/light/alias_table.h"
#include "scene/gltf/gltf_material.h"

namespace fh {
namespace glsl {
#include "lib/material/texture_address.glsl"
}  // namespace glsl
namespace {

// Relative luminance of linear Rec. 709 RGB (ITU-R BT.709 primaries).
double luminance(const glm::vec4& rgb) { return 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b; }

double triangle_area(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    const glm::dvec3 a(p0), b(p1), c(p2);
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// Emitted power of a punctual light, by luminance: what the alias table picks lights in proportion to. A
// directional light delivers irradiance E over the scene's bounding disc (pi r^2 E, as pbrt-v4).
double punctual_light_power(const SceneLight& light, double scene_radius) {
    const double i = luminance(glm::vec4(light.intensity, 0.0f));
    if (light.type == gpu::LIGHT_DIRECTIONAL) return glm::pi<double>() * scene_radius * scene_radius * i;
    if (light.type == gpu::LIGHT_SPOT)  // pbrt-v4 SpotLight::Phi: the cone between inner and outer counts half
        return 2.0 * glm::pi<double>() * i *
               (1.0 - 0.5 * (std::cos(double(light.inner_cone)) + std::cos(double(light.outer_cone))));
    return 4.0 * glm::pi<double>() * i;
}

gpu::PunctualLight pack_punctual_light(const SceneLight& light) {
    gpu::PunctualLight p{};
    p.position = gpu::vec4(glm::vec3(light.position), 1.0f);
    p.direction = gpu::vec4(glm::vec3(light.direction), 0.0f);
    p.intensity = gpu::vec4(light.intensity, 0.0f);
    p.type = light.type;
    p.cos_inner = float(std::cos(double(light.inner_cone)));
    p.cos_outer = float(std::cos(double(light.outer_cone)));
    return p;
}

uint32_t pack_half2(float a, float b) { return glm::packHalf2x16(glm::vec2(a, b)); }  // GLSL packHalf2x16

gpu::TriangleAttributes pack_attributes(const Scene& scene, size_t t) {
    gpu::TriangleAttributes a{};
    const glm::vec2* uv0 = &scene.texcoords0[3 * t];
    const glm::vec2* uv1 = &scene.texcoords1[3 * t];
    const glm::vec4* c = &scene.colors[3 * t];
    const glm::vec4* tg = &scene.tangents[3 * t];
    a.uv0_c01 = gpu::vec4(uv0[0], uv0[1]);
    a.uv0_c2_uv1_c0 = gpu::vec4(uv0[2], uv1[0]);
    a.uv1_c12 = gpu::vec4(uv1[1], uv1[2]);
    uint32_t* colors[3][2] = {{&a.color0_rg, &a.color0_ba}, {&a.color1_rg, &a.color1_ba}, {&a.color2_rg, &a.color2_ba}};
    uint32_t* tangents[3][2] = {{&a.tangent0_xy, &a.tangent0_zw}, {&a.tangent1_xy, &a.tangent1_zw},
                                {&a.tangent2_xy, &a.tangent2_zw}};
    for (int k = 0; k < 3; ++k) {
        *colors[k][0] = pack_half2(c[k].r, c[k].g);
        *colors[k][1] = pack_half2(c[k].b, c[k].a);
        *tangents[k][0] = pack_half2(tg[k].x, tg[k].y);
        *tangents[k][1] = pack_half2(tg[k].z, tg[k].w);
    }
    return a;
}

// Textures as the GPU reads them: the texels of every image a material slot uses, back to back (an image no
// slot reads, such as an occlusion map, is not uploaded: its entry has width 0).
void pack_textures(const Scene& scene, PackedScene& packed) {
    packed.texture_slots = scene.texture_slots;
    std::vector<uint8_t> used(scene.images.size(), 0);
    for (const gpu::TextureSlot& slot : scene.texture_slots)
        if (slot.image < used.size()) used[slot.image] = 1;
    size_t offset = 0;
    for (size_t i = 0; i < scene.images.size(); ++i) {
        const SceneImage& image = scene.images[i];
        packed.texture_images.push_back(used[i] ? gpu::TextureImage{uint32_t(offset), image.width, image.height, 0u}
                                                : gpu::TextureImage{0u, 0u, 0u, 0u});
        if (used[i]) offset += image.texels.size();
        if (offset > 0xffffffffu) throw std::length_error("pack.cpp: more than 2^32 texels");
    }
    packed.texels.reserve(offset);
    for (size_t i = 0; i < scene.images.size(); ++i)
        if (used[i]) packed.texels.insert(packed.texels.end(), scene.images[i].texels.begin(), scene.images[i].texels.end());
}

}  // namespace

std::vector<gpu::MaterialLayers> material_layers_of(const Scene& scene) {
    std::vector<gpu::MaterialLayers> layers = scene.material_layers;
    layers.resize(scene.materials.size(), gltf::make_default_layers());
    return layers;
}

double mean_emitted_luminance(const Scene& scene, size_t t, const gpu::Material& m) {
    const double factor = luminance(m.emission);
    if (m.emissive_texture == gpu::INVALID_INDEX || m.emissive_texture >= scene.texture_slots.size() ||
        scene.texcoords0.size() < 3 * (t + 1))
        return factor;
    const gpu::TextureSlot& slot = scene.texture_slots[m.emissive_texture];
    const SceneImage& image = scene.images[slot.image];
    const bool set1 = (slot.addressing & gpu::SAMPLER_TEXCOORD_1) != 0;
    const glm::vec2* uv = set1 ? &scene.texcoords1[3 * t] : &scene.texcoords0[3 * t];
    const glm::vec2 t0 = glsl::transform_texcoord(slot, uv[0]), t1 = glsl::transform_texcoord(slot, uv[1]),
                    t2 = glsl::transform_texcoord(slot, uv[2]);
    const uint32_t wrap_s = slot.addressing & 3u, wrap_t = (slot.addressing >> 2) & 3u;
    auto texel_at = [&](int x, int y) {
        x = glsl::wrap_texel(x, int(image.width), wrap_s);
        y = glsl::wrap_texel(y, int(image.height), wrap_t);
        return luminance(m.emission * glm::vec4(glm::vec3(glsl::decode_texel(image.texels[size_t(y) * image.width + size_t(x)], true)), 0.0f));
    };
    // The brightest texel under the triangle's texture-space bounding box (up to 2^20 texels; beyond, the box
    // counts as lit): black there means black everywhere, so the triangle is no light.
    const glm::vec2 lo = glm::min(t0, glm::min(t1, t2)) * glm::vec2(image.width, image.height);
    const glm::vec2 hi = glm::max(t0, glm::max(t1, t2)) * glm::vec2(image.width, image.height);
    double brightest = 0.0, box_texels = 0.0;
    if (std::isfinite(lo.x + lo.y + hi.x + hi.y) && std::max(glm::abs(lo).x, glm::abs(lo).y) < 1e8f &&
        std::max(glm::abs(hi).x, glm::abs(hi).y) < 1e8f && double(hi.x - lo.x + 1) * double(hi.y - lo.y + 1) <= double(1 << 20)) {
        for (int y = int(std::floor(lo.y)); y <= int(std::floor(hi.y)); ++y)
            for (int x = int(std::floor(lo.x)); x <= int(std::floor(hi.x)); ++x) {
                brightest = std::max(brightest, texel_at(x, y));
                box_texels += 1.0;
            }
        if (brightest == 0.0) return 0.0;
    } else {
        brightest = factor;
        box_texels = 1.0;
    }
    // The mean over the triangle: k x k strata with about 4 per texel covered, k in [4, 64], nearest texels.
    const glm::vec2 e1 = t1 - t0, e2 = t2 - t0;
    const double texels = 0.5 * std::abs(double(e1.x) * e2.y - double(e1.y) * e2.x) * image.width * image.height;
    const int k = int(std::clamp(std::ceil(2.0 * std::sqrt(std::isfinite(texels) ? texels : 1024.0)), 4.0, 64.0));
    double sum = 0.0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            // Uniform on the triangle (pbrt-v4 SampleUniformTriangle's square-root warp) at stratum centres.
            const double su = std::sqrt((i + 0.5) / k), v = (j + 0.5) / k;
            const float b1 = float(su * (1.0 - v)), b2 = float(su * v), b0 = 1.0f - b1 - b2;
            const glm::vec2 p = b0 * t0 + b1 * t1 + b2 * t2;
            sum += texel_at(int(std::floor(glsl::reduce_texcoord(p.x, wrap_s) * image.width)),
                            int(std::floor(glsl::reduce_texcoord(p.y, wrap_t) * image.height)));
        }
    // A bright spot between the strata still makes the triangle a light, picked in proportion to that spot
    // alone: the pick probability only shapes the noise, the estimate stays unbiased.
    return sum > 0.0 ? sum / (double(k) * k) : brightest / std::max(box_texels, 1.0);
}

namespace {

// mean_emitted_luminance of every triangle in leaf order whose material emits (0 for the others, which cannot be
// lights), on two threads: a textured emitter averages its texels per triangle, which took a fifth of DamagedHelmet's
// warm start. A pure function of each triangle, so the result does not depend on the split.
std::vector<double> measure_emitted_luminance(const Scene& scene, std::span<const uint32_t> triangle_order) {
    std::vector<double> emitted(triangle_order.size(), 0.0);
    constexpr size_t CHUNK = 1024;  // chunks dealt in turn to the threads: emitters cluster by material
    auto measure_chunks = [&](size_t first_chunk) {
        for (size_t begin = first_chunk * CHUNK; begin < emitted.size(); begin += 2 * CHUNK)
            for (size_t i = begin; i < std::min(begin + CHUNK, emitted.size()); ++i) {
                const size_t t = triangle_order[i];
                if (scene.triangle_material[t] >= scene.materials.size()) continue;  // pack_scene reports it
                const gpu::Material& m = scene.materials[scene.triangle_material[t]];
                if (m.emission.r > 0.0f || m.emission.g > 0.0f || m.emission.b > 0.0f)
                    emitted[i] = mean_emitted_luminance(scene, t, m);
            }
    };
    if (emitted.size() <= CHUNK) {
        measure_chunks(0);
        return emitted;
    }
    std::thread second(measure_chunks, 1);
    measure_chunks(0);
    second.join();
    return emitted;
}

}  // namespace

PackedScene pack_scene(const Scene& scene, const Bvh& bvh, EnvironmentMap environment) {
    if (!scene.instances.empty()) throw std::invalid_argument("pack.cpp: a scene with instances needs build_scene_bvh");
    return pack_scene(scene, make_single_level(bvh), std::move(environment));
}

PackedScene pack_scene(const Scene& scene, const SceneBvh& bvh, EnvironmentMap environment) {
    const size_t n = scene.triangle_count();
    if (bvh.triangle_order.size() != n || scene.normals.size() != scene.positions.size() ||
        scene.triangle_material.size() != n || scene.triangle_has_normals.size() != n)
        throw std::invalid_argument("pack.cpp: the BVH and the scene arrays disagree on the triangle count");

    PackedScene packed;
    packed.origin = scene.origin;
    packed.motion_segments = scene.motion_segments;
    packed.source = scene.source.string();
    packed.effects = analyse_effects(scene, !environment.empty());
    packed.nodes = bvh.nodes;
    packed.bounds_lo = bvh.bounds_lo;
    packed.bounds_hi = bvh.bounds_hi;
    check_render_range(scene, glm::dvec3(bvh.bounds_lo), glm::dvec3(bvh.bounds_hi), "the geometry");
    packed.instances = bvh.instances;
    packed.materials = scene.materials;
    packed.material_layers = material_layers_of(scene);
    packed.positions.resize(n);
    packed.shading.resize(n);
    const bool attributes = !scene.texcoords0.empty();
    if (attributes) {
        if (scene.texcoords0.size() != scene.positions.size() || scene.texcoords1.size() != scene.positions.size() ||
            scene.colors.size() != scene.positions.size() || scene.tangents.size() != scene.positions.size())
            throw std::invalid_argument("pack.cpp: the vertex attribute arrays disagree with the positions");
        packed.attributes.resize(n);
    }
    pack_textures(scene, packed);

    std::vector<uint32_t> emissive;  // leaf-order indices of emitting triangles
    std::set<uint32_t> emitting_materials;
    size_t moving_emitting_triangles = 0;
    std::vector<double> power, area;
    const std::vector<double> emitted = measure_emitted_luminance(scene, bvh.triangle_order);
    for (size_t i = 0; i < n; ++i) {
        const size_t t = bvh.triangle_order[i];
        const glm::vec3* p = &scene.positions[3 * t];
        const glm::vec3* nrm = &scene.normals[3 * t];
        packed.positions[i] = {p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z, uint32_t(t), 0u, 0.0f};
        if (attributes) packed.attributes[i] = pack_attributes(scene, t);
        gpu::TriangleShading& s = packed.shading[i];
        s = {nrm[0].x, nrm[0].y, nrm[0].z, nrm[1].x, nrm[1].y, nrm[1].z, nrm[2].x, nrm[2].y, nrm[2].z,
             scene.triangle_material[t], scene.triangle_has_normals[t] ? gpu::TRIANGLE_HAS_NORMALS : 0u, 0.0f};
        if (s.material >= scene.materials.size())
            throw std::invalid_argument("pack.cpp: triangle " + std::to_string(t) + " names material " +
                                        std::to_string(s.material) + " of " + std::to_string(scene.materials.size()));

        const gpu::Material& m = scene.materials[s.material];
        if (m.alpha_mode != gpu::ALPHA_OPAQUE) packed.positions[i].flags = gpu::TRIANGLE_ALPHA_TESTED;

        // Emitted power of a Lambertian emitter of radiance L over area A: pi L A per emitting side.
        const double a = triangle_area(p[0], p[1], p[2]);
        const double sides = (m.flags & gpu::MATERIAL_DOUBLE_SIDED) ? 2.0 : 1.0;
        const double w = emitted[i] * a * glm::pi<double>() * sides;
        const bool lit = a > 0.0 && w > 0.0 && (m.emission.r > 0.0f || m.emission.g > 0.0f || m.emission.b > 0.0f);
        // Only a mesh that moves during the shutter emits from an instance (the loader flattens the others): rays that
        // hit it see its light, but the light table (world-space triangles) leaves it out.
        if (lit && !scene.instances.empty() && t >= scene.world_triangle_count) {
            emitting_materials.insert(s.material);
            ++moving_emitting_triangles;
            continue;
        }
        if (lit) {
            emitting_materials.insert(s.material);
            emissive.push_back(uint32_t(i));
            power.push_back(w);
            area.push_back(a);
        }
    }
    const size_t triangle_lights = emissive.size();
    const double scene_radius = 0.5 * glm::length(scene.bounds_max - scene.bounds_min);
    for (size_t l = 0; l < scene.lights.size(); ++l) {
        const double w = punctual_light_power(scene.lights[l], scene_radius);
        if (!(w > 0.0)) continue;  // black lights are never picked
        emissive.push_back(gpu::PUNCTUAL_LIGHT_BIT | uint32_t(packed.punctual_lights.size()));
        packed.punctual_lights.push_back(pack_punctual_light(scene.lights[l]));
        const SceneLight& light = scene.lights[l];  // render space (the loader rebases lights)
        if (light.type != gpu::LIGHT_DIRECTIONAL) check_render_range(scene, light.position, light.position, "light " + std::to_string(l));
        power.push_back(w);
    }
    packed.moving_emitting_triangles = moving_emitting_triangles;
    decide_light_effects(packed.effects, emitting_materials, triangle_lights + moving_emitting_triangles,
                         packed.punctual_lights.size());
    decide_light_tree_effect(packed.effects, false, "NEE picks by the power table (--light-sampler decides: prepare_scene)");
    decide_camera_effects(packed.effects, false);  // a pinhole unless the render asks for a lens (prepare_scene)
    decide_motion_effects(packed.effects, scene.moving_instances > 0, scene.moving_instances, false);  // and the camera
    // The environment as a light over the scene's bounding disc: pi r^2 times the integral of its radiance
    // (a directional light's pi r^2 E, summed over directions; pbrt-v4 ImageInfiniteLight::Phi likewise).
    const bool environment_light = !environment.empty() && environment.luminance_integral > 0.0;
    if (environment_light) {
        emissive.push_back(gpu::ENVIRONMENT_LIGHT);
        power.push_back(glm::pi<double>() * std::max(scene_radius * scene_radius, 1e-30) * environment.luminance_integral);
    }
    packed.environment = std::move(environment);
    if (emissive.empty()) return packed;

    for (double w : power) packed.total_emitted_power += w;
    packed.emitter_power = power;
    const std::vector<AliasEntry> table = build_alias_table(power);
    packed.emitters.resize(emissive.size());
    for (size_t e = 0; e < emissive.size(); ++e) {
        const double pick_pdf = power[e] / packed.total_emitted_power;
        packed.emitters[e] = {emissive[e], float(table[e].threshold), table[e].alias, float(pick_pdf)};
        if (e < triangle_lights) packed.shading[emissive[e]].light_pdf_area = float(pick_pdf / area[e]);
        if (emissive[e] == gpu::ENVIRONMENT_LIGHT) packed.environment_pick_pdf = float(pick_pdf);
    }
    return packed;
}

uint32_t sample_alias(const std::vector<gpu::Emitter>& emitters, float u) {
    const uint32_t n = uint32_t(emitters.size());
    const float scaled = u * float(n);
    const uint32_t i = std::min(uint32_t(scaled), n - 1);
    const float rest = scaled - float(i);
    return rest < emitters[i].alias_threshold ? i : emitters[i].alias;
}

}  // namespace fh
