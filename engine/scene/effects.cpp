// Scene analysis for effects on demand: which EFFECT_* bits the stages must be compiled with.
#include "scene/effects.h"

#include <algorithm>
#include <initializer_list>
#include <set>
#include <stdexcept>

namespace fh {
namespace {

// Whether every texel of `image` has alpha 255.
bool is_opaque_image(const SceneImage& image) {
    for (uint32_t t : image.texels)
        if ((t >> 24) != 255u) return false;
    return true;
}

// Whether channel `channel` (0 = R) of every texel of `image` is 0.
bool is_zero_channel(const SceneImage& image, int channel) {
    for (uint32_t t : image.texels)
        if (((t >> (8 * channel)) & 0xffu) != 0u) return false;
    return true;
}

std::string list_materials(const std::set<uint32_t>& materials) {
    std::string out;
    size_t shown = 0;
    for (uint32_t m : materials) {
        if (shown++ == 6) {
            out += ", ...";
            break;
        }
        out += (out.empty() ? "material " : ", ") + std::to_string(m);
    }
    return out;
}

}  // namespace

const std::vector<EffectInfo>& list_effects();

namespace {

// Records one row of the effect table, switching the effect on when `on`.
void add_decision(SceneEffects& effects, EffectBits bit, bool on, std::string why) {
    if (on) effects.bits |= bit;
    for (const EffectInfo& e : list_effects())
        if (e.bit == bit) effects.decisions.push_back({bit, e.name, on, std::move(why)});
}

// Keeps the table in list_effects() order.
void sort_decisions(SceneEffects& effects) {
    auto rank = [](EffectBits bit) {
        const std::vector<EffectInfo>& all = list_effects();
        for (size_t i = 0; i < all.size(); ++i)
            if (all[i].bit == bit) return i;
        return all.size();
    };
    std::stable_sort(effects.decisions.begin(), effects.decisions.end(),
                     [&](const EffectDecision& a, const EffectDecision& b) { return rank(a.bit) < rank(b.bit); });
}

}  // namespace

const std::vector<EffectInfo>& list_effects() {
    static const std::vector<EffectInfo> effects = {
        {gpu::EFFECT_BASE_COLOR_TEXTURE, "base-color-texture"},
        {gpu::EFFECT_METALLIC_ROUGHNESS_TEXTURE, "metallic-roughness-texture"},
        {gpu::EFFECT_NORMAL_TEXTURE, "normal-texture"},
        {gpu::EFFECT_EMISSIVE_TEXTURE, "emissive-texture"},
        {gpu::EFFECT_VERTEX_COLORS, "vertex-colors"},
        {gpu::EFFECT_ALPHA, "alpha"},
        {gpu::EFFECT_SPECULAR, "specular"},
        {EFFECT_SPECULAR_TEXTURE, "specular-texture"},
        {EFFECT_GLOSSINESS_TEXTURE, "glossiness-texture"},
        {gpu::EFFECT_EMISSIVE_TRIANGLES, "emissive-triangles"},
        {gpu::EFFECT_PUNCTUAL_LIGHTS, "punctual-lights"},
        {gpu::EFFECT_LIGHT_TREE, "light-tree"},
        {gpu::EFFECT_ENVIRONMENT, "environment"},
        {gpu::EFFECT_TRANSMISSION, "transmission"},
        {gpu::EFFECT_TRANSMISSION_TEXTURE, "transmission-texture"},
        {gpu::EFFECT_VOLUME, "volume"},
        {gpu::EFFECT_ABSORPTION, "absorption"},
        {gpu::EFFECT_GLASS_MULTISCATTER, "glass-multiscatter"},
        {gpu::EFFECT_GGX_MULTISCATTER, "ggx-multiscatter"},
        {gpu::EFFECT_CLEARCOAT, "clearcoat"},
        {gpu::EFFECT_CLEARCOAT_TEXTURE, "clearcoat-texture"},
        {gpu::EFFECT_CLEARCOAT_NORMAL_TEXTURE, "clearcoat-normal-texture"},
        {gpu::EFFECT_UNLIT, "unlit"},
        {gpu::EFFECT_SHEEN, "sheen"},
        {gpu::EFFECT_SHEEN_TEXTURE, "sheen-texture"},
        {gpu::EFFECT_DIFFUSE_TRANSMISSION, "diffuse-transmission"},
        {gpu::EFFECT_DIFFUSE_TRANSMISSION_TEXTURE, "diffuse-transmission-texture"},
        {gpu::EFFECT_ANISOTROPY, "anisotropy"},
        {gpu::EFFECT_ANISOTROPY_TEXTURE, "anisotropy-texture"},
        {gpu::EFFECT_IRIDESCENCE, "iridescence"},
        {gpu::EFFECT_IRIDESCENCE_TEXTURE, "iridescence-texture"},
        {gpu::EFFECT_SPECTRAL, "spectral"},
        {gpu::EFFECT_THIN_LENS, "thin-lens"},
        {gpu::EFFECT_MOTION_BLUR, "motion-blur"},
    };
    return effects;
}

EffectBits find_switchable_effect(const std::string& name) {
    std::string names;
    for (const EffectInfo& e : list_effects()) {
        if (!(e.bit & SWITCHABLE_EFFECTS)) continue;
        if (name == e.name) return e.bit;
        names += (names.empty() ? "" : ", ") + std::string(e.name);
    }
    throw std::invalid_argument("unknown or not switchable effect '" + name + "' (" + names + ")");
}

std::string describe_effects(EffectBits bits) {
    std::string out;
    for (const EffectInfo& e : list_effects())
        if (bits & e.bit) out += (out.empty() ? "" : ",") + std::string(e.name);
    return out.empty() ? "none" : out;
}

SceneEffects analyse_effects(const Scene& scene, bool environment) {
    std::set<uint32_t> used;
    for (uint32_t m : scene.triangle_material) used.insert(m);
    // Instances of shared geometry may replace the mesh's material (SceneInstance::material).
    for (const SceneInstance& instance : scene.instances)
        if (instance.material != gpu::INVALID_INDEX && instance.material < scene.materials.size())
            used.insert(instance.material);
    bool colors_rgb = false, colors_alpha = false;
    for (const glm::vec4& c : scene.colors) {
        colors_rgb = colors_rgb || c.r != 1.0f || c.g != 1.0f || c.b != 1.0f;
        colors_alpha = colors_alpha || c.a != 1.0f;
    }
    auto slot_valid = [&](uint32_t slot) { return slot != gpu::INVALID_INDEX && slot < scene.texture_slots.size(); };
    // Whether the texture of a valid slot is 0 everywhere in each of `channels` (0 = R ... 3 = A).
    auto slot_zero = [&](uint32_t slot, std::initializer_list<int> channels) {
        const SceneImage& image = scene.images[scene.texture_slots[slot].image];
        return std::all_of(channels.begin(), channels.end(), [&](int c) { return is_zero_channel(image, c); });
    };

    std::set<uint32_t> base, metal_rough, normal, emissive, alpha, glass, glass_texture, volume, absorbing, rough_glass;
    std::set<uint32_t> coat, coat_texture, coat_normal, unlit, sheen, sheen_texture, diffuse, diffuse_texture;
    std::set<uint32_t> anisotropic, anisotropy_texture, film, film_texture, dispersive, specular, rough_specular;
    std::set<uint32_t> specular_texture, glossiness_texture;
    for (uint32_t m : used) {
        const gpu::Material& mat = scene.materials[m];
        // An unlit material shows its base colour only: none of its layers is ever evaluated.
        if (m < scene.material_layers.size() && !(mat.flags & gpu::MATERIAL_UNLIT)) {
            // The dielectric's lobes (glass, diffuse transmission) show unless the material is all metal.
            const bool dielectric = mat.metallic < 1.0f || slot_valid(mat.metallic_roughness_texture);
            // Glass shows where transmission > 0 on a dielectric.
            const gpu::MaterialLayers& layers = scene.material_layers[m];
            const bool has_texture = slot_valid(layers.transmission_texture);
            const bool visible = layers.transmission > 0.0f && dielectric &&
                                 !(has_texture && slot_zero(layers.transmission_texture, {0}));
            if (visible) {
                glass.insert(m);
                // Rough glass loses energy between its microfacets, given back by the multiple-scattering lobe; a
                // roughness factor of 0 keeps alpha at its minimum (texture or not), where nothing is lost.
                if (mat.roughness > 0.0f) rough_glass.insert(m);
                if (has_texture) glass_texture.insert(m);
                if (layers.flags & gpu::LAYERS_VOLUME) volume.insert(m);
                // Dispersion bends light by wavelength where it refracts into a volume (thin walls do not bend it).
                if ((layers.flags & gpu::LAYERS_VOLUME) && layers.dispersion > 0.0f) dispersive.insert(m);
                if ((layers.flags & gpu::LAYERS_VOLUME) &&
                    (layers.attenuation.x > 0.0f || layers.attenuation.y > 0.0f || layers.attenuation.z > 0.0f))
                    absorbing.insert(m);
            }
            // A coat shows where clearcoatFactor > 0 and its texture (if any) is not black; it covers metal too.
            const bool coat_textured = slot_valid(layers.clearcoat_texture);
            if (layers.clearcoat > 0.0f && !(coat_textured && slot_zero(layers.clearcoat_texture, {0}))) {
                coat.insert(m);
                // A rough coat loses light between its microfacets as the base's lobes do (--microfacet compensated);
                // clearcoatRoughnessTexture only multiplies the factor.
                if (layers.clearcoat_roughness > 0.0f) rough_specular.insert(m);
                if (coat_textured || (slot_valid(layers.clearcoat_roughness_texture) && layers.clearcoat_roughness > 0.0f))
                    coat_texture.insert(m);
                if (slot_valid(layers.clearcoat_normal_texture) &&
                    scene.texture_slots[layers.clearcoat_normal_texture].scale != 0.0f)
                    coat_normal.insert(m);
            }
            // A sheen shows where sheenColorFactor is not black and its colour texture (if any) is not black.
            const bool sheen_textured = slot_valid(layers.sheen_color_texture);
            if (std::max({layers.sheen.x, layers.sheen.y, layers.sheen.z}) > 0.0f &&
                !(sheen_textured && slot_zero(layers.sheen_color_texture, {0, 1, 2}))) {
                sheen.insert(m);
                if (sheen_textured || (slot_valid(layers.sheen_roughness_texture) && layers.sheen.w > 0.0f))
                    sheen_texture.insert(m);
            }
            // Diffuse transmission shows where its factor > 0 on a dielectric and its texture's alpha is not 0.
            const bool diffuse_textured = slot_valid(layers.diffuse_transmission_texture);
            if (layers.diffuse_transmission.w > 0.0f && dielectric &&
                !(diffuse_textured && slot_zero(layers.diffuse_transmission_texture, {3}))) {
                diffuse.insert(m);
                if (diffuse_textured || slot_valid(layers.diffuse_transmission_color_texture)) diffuse_texture.insert(m);
            }
            // Anisotropy shows where its strength > 0, its texture's strength (B) is not 0 everywhere, and the
            // roughness is below 1 (alpha 1 stretched towards 1 is still isotropic).
            const bool anisotropy_textured = slot_valid(layers.anisotropy_texture);
            if (layers.anisotropy_strength > 0.0f && (mat.roughness < 1.0f || slot_valid(mat.metallic_roughness_texture)) &&
                !(anisotropy_textured && slot_zero(layers.anisotropy_texture, {2}))) {
                anisotropic.insert(m);
                if (anisotropy_textured) anisotropy_texture.insert(m);
                // A stretched lobe (the metal's, or the specular layer's) is rough along its direction even at
                // roughness 0: it loses light between its microfacets (--microfacet compensated gives it back).
                if (mat.metallic > 0.0f || mat.specular_color.w > 0.0f) rough_specular.insert(m);
            }
            // A thin film shows where iridescenceFactor > 0, its texture's R is not 0 everywhere, and it has a
            // thickness (the maximum, or with a thickness texture either end of the range).
            const bool film_textured = slot_valid(layers.iridescence_texture);
            const bool thickness_textured = slot_valid(layers.iridescence_thickness_texture);
            const bool thick = layers.iridescence_thickness_max > 0.0f ||
                               (thickness_textured && layers.iridescence_thickness_min > 0.0f);
            if (layers.iridescence > 0.0f && thick && !(film_textured && slot_zero(layers.iridescence_texture, {0}))) {
                film.insert(m);
                if (film_textured || thickness_textured) film_texture.insert(m);
            }
        }
        if (mat.flags & gpu::MATERIAL_UNLIT) unlit.insert(m);
        // The base's GGX reflection shows unless the material is Lambertian: metallic 0 (a metallicRoughnessTexture
        // only multiplies the factor) and specularFactor 0 (no specular layer: f0 = f90 = 0). Unlit: never evaluated.
        if (!(mat.flags & gpu::MATERIAL_UNLIT) && (mat.metallic > 0.0f || mat.specular_color.w > 0.0f)) specular.insert(m);
        // KHR_materials_specular textures multiply the dielectric's factors: they show where the specular layer does
        // (specularFactor > 0, some metallic below 1) and, for the colour, where specularColorFactor is not black. A
        // specular-glossiness map's alpha sets the roughness where glossinessFactor > 0 (roughness factor < 1).
        const bool dielectric_specular = !(mat.flags & gpu::MATERIAL_UNLIT) && mat.specular_color.w > 0.0f &&
                                         (mat.metallic < 1.0f || slot_valid(mat.metallic_roughness_texture));
        const bool colored = mat.specular_color.x > 0.0f || mat.specular_color.y > 0.0f || mat.specular_color.z > 0.0f;
        if (dielectric_specular && (slot_valid(mat.specular_texture) || (slot_valid(mat.specular_color_texture) && colored)))
            specular_texture.insert(m);
        if (dielectric_specular && slot_valid(mat.specular_color_texture) &&
            (mat.flags & gpu::MATERIAL_GLOSSINESS_IN_ALPHA) && mat.roughness < 1.0f)
            glossiness_texture.insert(m);
        // A rough GGX lobe (metal, or the dielectric's specular layer) loses energy between its microfacets, given back
        // by the multiple-scattering lobe (--microfacet compensated); metallic-roughness textures only multiply the
        // factors, so a factor of 0 keeps the product 0, but a specular-glossiness map's alpha raises it.
        const bool glossiness_mapped = slot_valid(mat.specular_color_texture) && (mat.flags & gpu::MATERIAL_GLOSSINESS_IN_ALPHA);
        const bool rough = !(mat.flags & gpu::MATERIAL_UNLIT) && (mat.roughness > 0.0f || glossiness_mapped);
        if (rough && (mat.metallic > 0.0f || dielectric_specular)) rough_specular.insert(m);
        const bool black_emission = mat.emission.r == 0.0f && mat.emission.g == 0.0f && mat.emission.b == 0.0f;
        if (slot_valid(mat.base_color_texture)) base.insert(m);
        // Metallic and roughness textures multiply their factors; a factor of 0 keeps the product 0.
        if (slot_valid(mat.metallic_roughness_texture) && (mat.metallic > 0.0f || mat.roughness > 0.0f))
            metal_rough.insert(m);
        if (slot_valid(mat.normal_texture) && mat.normal_texture < scene.texture_slots.size() &&
            scene.texture_slots[mat.normal_texture].scale != 0.0f)
            normal.insert(m);
        if (slot_valid(mat.emissive_texture) && !black_emission) emissive.insert(m);
        if (mat.alpha_mode != gpu::ALPHA_OPAQUE) {
            const bool textured_alpha =
                slot_valid(mat.base_color_texture) &&
                !is_opaque_image(scene.images[scene.texture_slots[mat.base_color_texture].image]);
            const bool variable = textured_alpha || colors_alpha;
            const float a = mat.base_color.a;
            const bool always_present = mat.alpha_mode == gpu::ALPHA_MASK ? a >= mat.alpha_cutoff && !variable
                                                                          : a >= 1.0f && !variable;
            if (!always_present) alpha.insert(m);
        }
    }

    SceneEffects effects;
    auto decide = [&](EffectBits bit, bool on, std::string why) { add_decision(effects, bit, on, std::move(why)); };
    auto by_materials = [&](EffectBits bit, const std::set<uint32_t>& materials, const char* absent) {
        decide(bit, !materials.empty(), materials.empty() ? absent : list_materials(materials));
    };
    by_materials(gpu::EFFECT_BASE_COLOR_TEXTURE, base, "no visible material has a baseColorTexture");
    by_materials(gpu::EFFECT_METALLIC_ROUGHNESS_TEXTURE, metal_rough,
                 "no visible material has a metallicRoughnessTexture with non-zero factors");
    by_materials(gpu::EFFECT_NORMAL_TEXTURE, normal, "no visible material has a normalTexture of non-zero scale");
    by_materials(gpu::EFFECT_EMISSIVE_TEXTURE, emissive,
                 "no visible material has an emissiveTexture with a non-zero emissiveFactor");
    decide(gpu::EFFECT_VERTEX_COLORS, colors_rgb || colors_alpha,
           colors_rgb || colors_alpha ? "COLOR_0 is not white everywhere" : "no COLOR_0, or white everywhere");
    by_materials(gpu::EFFECT_ALPHA, alpha, "every visible material is opaque (OPAQUE, or alpha 1 everywhere)");
    by_materials(gpu::EFFECT_SPECULAR, specular,
                 "every visible material is Lambertian (metallic 0 and KHR_materials_specular specularFactor 0)");
    by_materials(EFFECT_SPECULAR_TEXTURE, specular_texture,
                 "no visible dielectric specular layer has a KHR_materials_specular or specular-glossiness texture");
    by_materials(EFFECT_GLOSSINESS_TEXTURE, glossiness_texture,
                 "no visible material has a specularGlossinessTexture with glossinessFactor > 0");
    decide(gpu::EFFECT_ENVIRONMENT, environment, environment ? "--env or --background" : "no --env or --background");
    by_materials(gpu::EFFECT_TRANSMISSION, glass,
                 "no visible material has KHR_materials_transmission > 0 on a dielectric");
    by_materials(gpu::EFFECT_TRANSMISSION_TEXTURE, glass_texture, "no glass material has a transmissionTexture");
    by_materials(gpu::EFFECT_VOLUME, volume, "no glass material has KHR_materials_volume thicknessFactor > 0");
    by_materials(gpu::EFFECT_ABSORPTION, absorbing,
                 "no volume has a finite attenuationDistance with an attenuationColor below 1");
    by_materials(gpu::EFFECT_GLASS_MULTISCATTER, rough_glass, "no glass material has a roughness above 0");
    by_materials(gpu::EFFECT_GGX_MULTISCATTER, rough_specular,
                 "no visible material has a rough GGX lobe (a metal, a specular layer or a clear coat, with a roughness above 0)");
    by_materials(gpu::EFFECT_CLEARCOAT, coat, "no visible material has KHR_materials_clearcoat clearcoatFactor > 0");
    by_materials(gpu::EFFECT_CLEARCOAT_TEXTURE, coat_texture,
                 "no coated material has a clearcoatTexture or a clearcoatRoughnessTexture with a non-zero factor");
    by_materials(gpu::EFFECT_CLEARCOAT_NORMAL_TEXTURE, coat_normal,
                 "no coated material has a clearcoatNormalTexture of non-zero scale");
    by_materials(gpu::EFFECT_UNLIT, unlit, "no visible material has KHR_materials_unlit");
    by_materials(gpu::EFFECT_SHEEN, sheen, "no visible material has a KHR_materials_sheen sheenColor above black");
    by_materials(gpu::EFFECT_SHEEN_TEXTURE, sheen_texture,
                 "no sheen has a sheenColorTexture or a sheenRoughnessTexture with a non-zero factor");
    by_materials(gpu::EFFECT_DIFFUSE_TRANSMISSION, diffuse,
                 "no visible material has KHR_materials_diffuse_transmission > 0 on a dielectric");
    by_materials(gpu::EFFECT_DIFFUSE_TRANSMISSION_TEXTURE, diffuse_texture,
                 "no diffusely transmitting material has a diffuseTransmissionTexture or ...ColorTexture");
    by_materials(gpu::EFFECT_ANISOTROPY, anisotropic,
                 "no visible material has KHR_materials_anisotropy strength > 0 with roughness < 1");
    by_materials(gpu::EFFECT_ANISOTROPY_TEXTURE, anisotropy_texture, "no anisotropic material has an anisotropyTexture");
    by_materials(gpu::EFFECT_IRIDESCENCE, film,
                 "no visible material has KHR_materials_iridescence > 0 with a film thicker than 0 nm");
    by_materials(gpu::EFFECT_IRIDESCENCE_TEXTURE, film_texture,
                 "no iridescent material has an iridescenceTexture or an iridescenceThicknessTexture");
    by_materials(gpu::EFFECT_SPECTRAL, dispersive,
                 "no visible volume (glass, thicknessFactor > 0) has KHR_materials_dispersion > 0");
    return effects;
}

void decide_light_effects(SceneEffects& effects, const std::set<uint32_t>& emitting_materials, size_t emitting_triangles,
                          size_t punctual_lights) {
    auto decide = [&](EffectBits bit, bool on, std::string why) { add_decision(effects, bit, on, std::move(why)); };
    decide(gpu::EFFECT_EMISSIVE_TRIANGLES, emitting_triangles > 0,
           emitting_triangles > 0 ? std::to_string(emitting_triangles) + " emitting triangles, " +
                                        list_materials(emitting_materials)
                                  : "no triangle emits (emissive factor, texture and area all non-zero)");
    decide(gpu::EFFECT_PUNCTUAL_LIGHTS, punctual_lights > 0,
           punctual_lights > 0 ? std::to_string(punctual_lights) + " KHR_lights_punctual lights"
                               : "no KHR_lights_punctual light of non-zero power");
    sort_decisions(effects);
}

void decide_light_tree_effect(SceneEffects& effects, bool tree, std::string why) {
    effects.bits &= ~EffectBits(gpu::EFFECT_LIGHT_TREE);
    std::erase_if(effects.decisions, [](const EffectDecision& d) { return d.bit == gpu::EFFECT_LIGHT_TREE; });
    add_decision(effects, gpu::EFFECT_LIGHT_TREE, tree, std::move(why));
    sort_decisions(effects);
}

void decide_microfacet_effects(SceneEffects& effects, bool compensated) {
    if (compensated || !(effects.bits & gpu::EFFECT_GGX_MULTISCATTER)) return;
    effects.bits &= ~EffectBits(gpu::EFFECT_GGX_MULTISCATTER);
    std::erase_if(effects.decisions, [](const EffectDecision& d) { return d.bit == gpu::EFFECT_GGX_MULTISCATTER; });
    add_decision(effects, gpu::EFFECT_GGX_MULTISCATTER, false, "--microfacet single (the spec's single scattering)");
    sort_decisions(effects);
}

void decide_camera_effects(SceneEffects& effects, bool thin_lens) {
    effects.bits &= ~EffectBits(gpu::EFFECT_THIN_LENS);
    std::erase_if(effects.decisions, [](const EffectDecision& d) { return d.bit == gpu::EFFECT_THIN_LENS; });
    add_decision(effects, gpu::EFFECT_THIN_LENS, thin_lens,
                 thin_lens ? "--aperture or --aperture-radius above 0" : "a pinhole camera (no --aperture)");
    sort_decisions(effects);
}

void decide_motion_effects(SceneEffects& effects, bool has_shutter, size_t moving_instances, bool camera_moves) {
    effects.bits &= ~EffectBits(gpu::EFFECT_MOTION_BLUR);
    std::erase_if(effects.decisions, [](const EffectDecision& d) { return d.bit == gpu::EFFECT_MOTION_BLUR; });
    std::string why = !has_shutter ? "no --shutter"
                                   : "nothing moves during the shutter (no instance, and not the camera)";
    if (has_shutter && (moving_instances > 0 || camera_moves)) {
        why = moving_instances > 0 ? std::to_string(moving_instances) + " instance(s) move during the shutter" : "";
        if (camera_moves) why += std::string(why.empty() ? "" : ", ") + "the camera moves during the shutter";
    }
    add_decision(effects, gpu::EFFECT_MOTION_BLUR, has_shutter && (moving_instances > 0 || camera_moves), why);
    sort_decisions(effects);
}

EffectBits select_effects(EffectBits analysed, EffectBits forced, EffectBits disabled) {
    return (analysed | (forced & SWITCHABLE_EFFECTS)) & ~(disabled & SWITCHABLE_EFFECTS);
}

}  // namespace fh
