// A material's KHR_materials_diffuse_transmission at a surface point: the share of the diffuse lobe sent through
// the surface and its colour (factors times textures). Compiled only for the effects the scene has
// (EFFECT_DIFFUSE_TRANSMISSION, EFFECT_DIFFUSE_TRANSMISSION_TEXTURE); the lobe is in bsdf.glsl.
#ifndef FH_DIFFUSE_TRANSMISSION_GLSL
#define FH_DIFFUSE_TRANSMISSION_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/material.glsl"

struct DiffuseTransmission {
    float factor;  // diffuseTransmissionFactor x A of diffuseTransmissionTexture
    vec3 color;    // diffuseTransmissionColorFactor x RGB of diffuseTransmissionColorTexture (sRGB-decoded)
};

DiffuseTransmission eval_diffuse_transmission(uint material, uint triangle, float b1, float b2) {
    DiffuseTransmission d;
    d.factor = 0.0f;
    d.color = vec3(1.0f);
    if (!effect_on(EFFECT_DIFFUSE_TRANSMISSION)) return d;
    vec4 factors = load_material_layers(material).diffuse_transmission;
    d.factor = factors.w;
    d.color = vec3(factors);
    if (effect_on(EFFECT_DIFFUSE_TRANSMISSION_TEXTURE) && d.factor > 0.0f) {
        LayerTexels t = sample_layer_textures(load_material_layers(material).diffuse_transmission_texture,
                                              load_material_layers(material).diffuse_transmission_color_texture, triangle,
                                              b1, b2);
        d.factor *= t.first.w;
        d.color *= vec3(t.second);
    }
    return d;
}
#endif
