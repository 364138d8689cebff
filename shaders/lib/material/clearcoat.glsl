// A material's KHR_materials_clearcoat at a surface point: the coat's weight, roughness and normal (factors
// times textures). Compiled only for the effects the scene has (EFFECT_CLEARCOAT, EFFECT_CLEARCOAT_TEXTURE,
// EFFECT_CLEARCOAT_NORMAL_TEXTURE); the coat lobe itself is in bsdf.glsl.
#ifndef FH_CLEARCOAT_GLSL
#define FH_CLEARCOAT_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/material.glsl"

struct ClearcoatLayer {
    float weight;     // clearcoatFactor x R of clearcoatTexture
    float roughness;  // clearcoatRoughnessFactor x G of clearcoatRoughnessTexture
};

ClearcoatLayer eval_clearcoat_layer(uint material, uint triangle, float b1, float b2) {
    ClearcoatLayer c;
    c.weight = 0.0f;
    c.roughness = 0.0f;
    if (!effect_on(EFFECT_CLEARCOAT)) return c;
    c.weight = load_material_layers(material).clearcoat;
    c.roughness = load_material_layers(material).clearcoat_roughness;
    if (effect_on(EFFECT_CLEARCOAT_TEXTURE) && c.weight > 0.0f) {
        LayerTexels t = sample_layer_textures(load_material_layers(material).clearcoat_texture,
                                              load_material_layers(material).clearcoat_roughness_texture, triangle, b1, b2);
        c.weight *= t.first.x;
        c.roughness *= t.second.y;
    }
    return c;
}

// The coat's normal: `n` (the interpolated normal: the base's normalTexture does not apply to the coat, as the
// extension says) with the clearcoatNormalTexture applied when there is one.
vec3 apply_clearcoat_normal_texture(uint material, uint triangle, float b1, float b2, vec3 n) {
    if (!effect_on(EFFECT_CLEARCOAT_NORMAL_TEXTURE)) return n;
    uint slot = load_material_layers(material).clearcoat_normal_texture;
    return slot == INVALID_INDEX ? n : apply_normal_map(slot, triangle, b1, b2, n);
}
#endif
