// A material's KHR_materials_sheen at a surface point: the sheen's colour and roughness (factors times
// textures). Compiled only for the effects the scene has (EFFECT_SHEEN, EFFECT_SHEEN_TEXTURE); the lobe is in
// sheen.glsl and its layering in bsdf.glsl.
#ifndef FH_SHEEN_LAYER_GLSL
#define FH_SHEEN_LAYER_GLSL
#include "effects.glsl"
#include "material.glsl"

struct SheenLayer {
    vec3 color;       // sheenColorFactor x RGB of sheenColorTexture (sRGB-decoded)
    float roughness;  // sheenRoughnessFactor x A of sheenRoughnessTexture
};

SheenLayer eval_sheen_layer(uint material, uint triangle, float b1, float b2) {
    SheenLayer s;
    s.color = vec3(0.0f);
    s.roughness = 0.0f;
    if (!effect_on(EFFECT_SHEEN)) return s;
    vec4 factors = material_layers[material].sheen;
    s.color = vec3(factors);
    s.roughness = factors.w;
    if (effect_on(EFFECT_SHEEN_TEXTURE) && max_value(s.color) > 0.0f) {
        uint color_slot = material_layers[material].sheen_color_texture;
        uint roughness_slot = material_layers[material].sheen_roughness_texture;
        if (color_slot != INVALID_INDEX || roughness_slot != INVALID_INDEX) {
            Texcoords tc = interpolate_texcoords(triangle, b1, b2);
            if (color_slot != INVALID_INDEX) s.color *= vec3(sample_texture(color_slot, tc));
            if (roughness_slot != INVALID_INDEX) s.roughness *= sample_texture(roughness_slot, tc).w;
        }
    }
    return s;
}
#endif
