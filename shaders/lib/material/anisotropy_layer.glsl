// A material's KHR_materials_anisotropy at a surface point: the strength and the direction of the stretched
// roughness (factors times the texture, in the mesh's tangent frame). Compiled only for the effects the scene has
// (EFFECT_ANISOTROPY, EFFECT_ANISOTROPY_TEXTURE); the anisotropic GGX is in ggx.glsl, its use in bsdf.glsl.
#ifndef FH_ANISOTROPY_LAYER_GLSL
#define FH_ANISOTROPY_LAYER_GLSL
#include "lib/core/effects.glsl"
#include "lib/material/material.glsl"

struct AnisotropyLayer {
    float strength;   // anisotropyStrength x B of anisotropyTexture
    vec3 direction;   // unit, in the tangent plane of the normal given (0 where the mesh has no tangent frame)
};

// The extension's direction: the texture's RG in [-1, 1] (default (1, 0): the tangent), rotated counter-clockwise
// by anisotropyRotation in the tangent frame, the frame's t and b from TANGENT or texture coordinates (those of the
// anisotropyTexture, else set 0) about `n`. A mesh without a tangent frame gets strength 0: isotropic.
AnisotropyLayer eval_anisotropy_layer(uint material, uint triangle, float b1, float b2, vec3 n) {
    AnisotropyLayer a;
    a.strength = 0.0f;
    a.direction = vec3(0.0f);
    if (!effect_on(EFFECT_ANISOTROPY)) return a;
    float strength = load_material_layers(material).anisotropy_strength;
    if (!(strength > 0.0f)) return a;
    vec2 d = vec2(1.0f, 0.0f);
    bool set1 = false;
    uint slot = load_material_layers(material).anisotropy_texture;
    if (effect_on(EFFECT_ANISOTROPY_TEXTURE) && slot != INVALID_INDEX) {
        vec3 texel = vec3(sample_texture(slot, interpolate_texcoords(triangle, b1, b2)));
        d = vec2(texel) * 2.0f - 1.0f;
        strength *= texel.z;
        set1 = (load_texture_slot(slot).addressing & SAMPLER_TEXCOORD_1) != 0u;
    }
    float c = load_material_layers(material).anisotropy_cos;
    float s = load_material_layers(material).anisotropy_sin;
    d = vec2(c * d.x - s * d.y, s * d.x + c * d.y);
    TangentFrame f = build_tangent_frame(set1, triangle, b1, b2, n);
    vec3 direction = f.t * d.x + f.b * d.y;
    float len = length(direction);
    if (!f.valid || !(len > 0.0f) || isinf(len)) return a;
    a.strength = strength;
    a.direction = direction / len;
    return a;
}
#endif
