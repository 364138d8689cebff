// A material's KHR_materials_sheen at a surface point: the sheen's colour and roughness (factors times
// textures). Compiled only for the effects the scene has (EFFECT_SHEEN, EFFECT_SHEEN_TEXTURE); the lobe is in
// sheen.glsl and its layering in bsdf.glsl.
#ifndef FH_SHEEN_LAYER_GLSL
#define FH_SHEEN_LAYER_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/material.glsl"

struct SheenLayer {
    vec3 color;       // sheenColorFactor x RGB of sheenColorTexture (sRGB-decoded)
    float roughness;  // sheenRoughnessFactor x A of sheenRoughnessTexture
};

SheenLayer eval_sheen_layer(uint material, uint triangle, float b1, float b2) {
    SheenLayer s;
    s.color = vec3(0.0f);
    s.roughness = 0.0f;
    if (!effect_on(EFFECT_SHEEN)) return s;
    vec4 factors = load_material_layers(material).sheen;
    s.color = vec3(factors);
    s.roughness = factors.w;
    if (effect_on(EFFECT_SHEEN_TEXTURE) && max_value(s.color) > 0.0f) {
        LayerTexels t = sample_layer_textures(load_material_layers(material).sheen_color_texture,
                                              load_material_layers(material).sheen_roughness_texture, triangle, b1, b2);
        s.color *= vec3(t.first);
        s.roughness *= t.second.w;
    }
    return s;
}
#endif
