// A material's KHR_materials_transmission and KHR_materials_volume at a surface point, and Beer-Lambert
// absorption along a path segment inside a volume. Compiled only for the effects the scene has
// (EFFECT_TRANSMISSION, EFFECT_TRANSMISSION_TEXTURE, EFFECT_VOLUME, EFFECT_ABSORPTION).
#ifndef FH_TRANSMISSION_GLSL
#define FH_TRANSMISSION_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/texture.glsl"
#include "lib/spectral/spectrum.glsl"

// transmissionFactor times the R channel of transmissionTexture at barycentrics (b1, b2) of `triangle`.
float eval_transmission(uint material, uint triangle, float b1, float b2) {
    if (!effect_on(EFFECT_TRANSMISSION)) return 0.0f;
    float transmission = load_material_layers(material).transmission;
    if (effect_on(EFFECT_TRANSMISSION_TEXTURE) && transmission > 0.0f) {
        uint slot = load_material_layers(material).transmission_texture;
        if (slot != INVALID_INDEX) transmission *= sample_texture(slot, interpolate_texcoords(triangle, b1, b2)).x;
    }
    return transmission;
}

// Whether the material's mesh bounds a volume that light refracts into (else its transmission is thin-walled).
bool encloses_volume(uint material) {
    return effect_on(EFFECT_VOLUME) && (load_material_layers(material).flags & LAYERS_VOLUME) != 0u;
}

// Whether paths remember the volume they are in (layout.h BINDING_PATH_MEDIA): for absorption, and so that
// Russian roulette can see through the radiance scaling 1 / eta^2 that refraction into a volume applies.
bool tracks_media() {
    return effect_on(EFFECT_VOLUME) || effect_on(EFFECT_ABSORPTION);
}

// Nested volumes (layout.h MEDIUM_STACK_SIZE): `media` lists the volumes a path is in, innermost first. Entering the
// volume of `material` puts it in front (the innermost replaces the outer ones while inside it); leaving takes it out
// wherever it is (overlapping meshes leave in any order); leaving one the path is not in changes nothing.
uvec4 enter_medium(uvec4 media, uint material) {
    return uvec4(material, media.x, media.y, media.z);
}
uvec4 leave_medium(uvec4 media, uint material) {
    if (media.x == material) return uvec4(media.y, media.z, media.w, INVALID_INDEX);
    if (media.y == material) return uvec4(media.x, media.z, media.w, INVALID_INDEX);
    if (media.z == material) return uvec4(media.x, media.y, media.w, INVALID_INDEX);
    if (media.w == material) return uvec4(media.x, media.y, media.z, INVALID_INDEX);
    return media;
}
// The refractive index of the volume of `medium` (INVALID_INDEX: outside every volume, 1).
float medium_ior(uint medium) {
    return medium == INVALID_INDEX ? 1.0f : max(load_material(medium).ior, 1.0e-4f);
}

// The refraction eta (n beyond / n here) of the surface of the volume of `material` (index `ior`) for a path arriving
// on the side `front` of its geometric normal inside the volumes `media`: the outer volume's index, not air's, at a
// nested interface. Leaving a volume that is not the innermost (overlapping meshes) changes nothing on either side:
// eta 1.
float refraction_eta_at(uint material, float ior, uvec4 media, bool front) {
    if (front) return ior / medium_ior(media.x);
    float here = media.x == material ? max(ior, 1.0e-4f) : medium_ior(media.x);
    return medium_ior(leave_medium(media, material).x) / here;
}

// What Russian roulette multiplies the throughput by inside the volume of `medium`: its ior^2, which undoes the
// 1 / eta^2 of entering it (pbrt-v4's etaScale), so that a path is not rouletted for a scaling it will get
// back on the way out (that made fireflies of up to 5x in a white furnace around a glass sphere).
float roulette_scale(uint medium) {
    if (!tracks_media() || medium == INVALID_INDEX) return 1.0f;
    float ior = load_material(medium).ior;
    return ior * ior;
}

// What light from the environment is multiplied by when it reaches a path that is still inside the volume of `medium`:
// its ior^2. A closed mesh never lets that happen. An open one (a hole, as Blender's Suzanne has at its eyes) lets a
// path leave its volume without crossing a surface; this gives back the eta^2 that crossing would have, so the path is
// not left darkened by the 1 / eta^2 of the surface it entered by (shaders/lib/bsdf/README.md "Glass", "Open meshes").
float escape_scale(uint medium) {
    return roulette_scale(medium);
}

// Beer-Lambert transmittance over distance t (may be infinite) inside the volume of material `medium`
// (INVALID_INDEX: outside every volume, 1). A channel that does not absorb stays 1 even for t = inf.
vec3 eval_medium_transmittance(uint medium, float t) {
    if (!effect_on(EFFECT_ABSORPTION) || medium == INVALID_INDEX) return vec3(1.0f);
    vec3 sigma = load_material_layers(medium).attenuation.xyz;
    return vec3(sigma.x > 0.0f ? exp(-sigma.x * t) : 1.0f, sigma.y > 0.0f ? exp(-sigma.y * t) : 1.0f,
                sigma.z > 0.0f ? exp(-sigma.z * t) : 1.0f);
}
// The same at the path's wavelengths: the absorption coefficient's spectrum is that of its RGB (spectrum.glsl), and
// a wavelength it does not absorb stays 1. For an RGB render, (the above, 0).
vec4 eval_path_medium_transmittance(SpectralFrame f, uint medium, float t) {
    if (!effect_on(EFFECT_SPECTRAL)) return vec4(eval_medium_transmittance(medium, t), 0.0f);
    if (!effect_on(EFFECT_ABSORPTION) || medium == INVALID_INDEX) return vec4(1.0f);
    vec4 sigma = upsample_rgb(f, load_material_layers(medium).attenuation.xyz);
    vec4 transmittance;
    for (int k = 0; k < 4; ++k) transmittance[k] = sigma[k] > 0.0f ? exp(-sigma[k] * t) : 1.0f;
    return transmittance;
}
#endif
