// A material's KHR_materials_iridescence at a surface point: the film's weight, thickness and index, and the
// host's bound of its Fresnel (MaterialLayers.iridescence_albedo_f0, _f90). Compiled only for the effects the scene has
// (EFFECT_IRIDESCENCE, EFFECT_IRIDESCENCE_TEXTURE); the film's Fresnel is in thin_film.glsl and its layering in
// bsdf.glsl.
#ifndef FH_IRIDESCENCE_LAYER_GLSL
#define FH_IRIDESCENCE_LAYER_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/material.glsl"

struct IridescenceLayer {
    float weight;     // iridescenceFactor x R of iridescenceTexture
    float thickness;  // nm: mix(minimum, maximum, G of iridescenceThicknessTexture), the maximum without it
    float ior;        // iridescenceIor
    vec2 albedo_bound;  // the bound's (a, b) (scene/thin_film_bound.h)
};

IridescenceLayer eval_iridescence_layer(uint material, uint triangle, float b1, float b2) {
    IridescenceLayer f;
    f.weight = 0.0f;
    f.thickness = 0.0f;
    f.ior = 1.0f;
    f.albedo_bound = vec2(0.0f);
    if (!effect_on(EFFECT_IRIDESCENCE)) return f;
    f.weight = load_material_layers(material).iridescence;
    if (!(f.weight > 0.0f)) return f;
    f.thickness = load_material_layers(material).iridescence_thickness_max;
    f.ior = load_material_layers(material).iridescence_ior;
    f.albedo_bound = vec2(load_material_layers(material).iridescence_albedo_f0,
                          load_material_layers(material).iridescence_albedo_f90);
    if (effect_on(EFFECT_IRIDESCENCE_TEXTURE)) {
        uint thickness_slot = load_material_layers(material).iridescence_thickness_texture;
        LayerTexels t = sample_layer_textures(load_material_layers(material).iridescence_texture, thickness_slot,
                                              triangle, b1, b2);
        f.weight *= t.first.x;
        if (thickness_slot != INVALID_INDEX)
            f.thickness = mix(load_material_layers(material).iridescence_thickness_min, f.thickness, t.second.y);
    }
    return f;
}
#endif
