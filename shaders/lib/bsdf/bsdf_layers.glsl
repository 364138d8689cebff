// The layers a surface's BSDF gets on top of its base and glass (shade.comp, light_shade.comp): thin film, anisotropy,
// diffuse transmission, sheen, clear coat, each compiled in only when the scene has it. The
// BSDF_HAS_* switches follow the scene's effects (specialization constants).
#ifndef FH_BSDF_LAYERS_GLSL
#define FH_BSDF_LAYERS_GLSL
#include "lib/core/effects.glsl"
#define BSDF_HAS_SPECULAR effect_on(EFFECT_SPECULAR)
#define BSDF_HAS_TRANSMISSION effect_on(EFFECT_TRANSMISSION)
#define BSDF_HAS_CLEARCOAT effect_on(EFFECT_CLEARCOAT)
#define BSDF_HAS_SHEEN effect_on(EFFECT_SHEEN)
#define BSDF_HAS_DIFFUSE_TRANSMISSION effect_on(EFFECT_DIFFUSE_TRANSMISSION)
#define BSDF_HAS_ANISOTROPY effect_on(EFFECT_ANISOTROPY)
#define BSDF_HAS_IRIDESCENCE effect_on(EFFECT_IRIDESCENCE)
#define BSDF_HAS_GLASS_MULTISCATTER effect_on(EFFECT_GLASS_MULTISCATTER)
#define BSDF_HAS_GGX_MULTISCATTER effect_on(EFFECT_GGX_MULTISCATTER)
#include "lib/bsdf/bsdf.glsl"
#include "lib/material/clearcoat.glsl"
#include "lib/material/sheen_layer.glsl"
#include "lib/material/diffuse_transmission.glsl"
#include "lib/material/anisotropy_layer.glsl"
#include "lib/material/iridescence_layer.glsl"
#include "lib/geometry/surface.glsl"

// bsdf with the layers of surface s (hit on `triangle` at b1, b2) in `frame` (z: the shading normal on wo's side);
// front: wo on the side of s.ng; ng: the geometric normal on wo's side; anisotropy: its layer, or strength 0.
BsdfParams add_bsdf_layers(BsdfParams bsdf, SurfaceHit s, uint triangle, float b1, float b2, Frame frame,
                           AnisotropyLayer anisotropy, bool front, vec3 ng, vec3 wo) {
    // Thin film (KHR_materials_iridescence) on the specular lobes; before anisotropy, which renormalises.
    if (effect_on(EFFECT_IRIDESCENCE)) {
        IridescenceLayer film = eval_iridescence_layer(s.material, triangle, b1, b2);
        bsdf = with_iridescence(bsdf, film.weight, film.thickness, film.ior, film.albedo_bound);
    }
    // Anisotropy (KHR_materials_anisotropy): the specular lobes' roughness stretched along a tangent direction.
    if (effect_on(EFFECT_ANISOTROPY) && anisotropy.strength > 0.0f)
        bsdf = with_anisotropy(bsdf, anisotropy.strength, vec2(to_local(frame, s.ta)));
    // Diffuse transmission (KHR_materials_diffuse_transmission): part of the Lambert lobe goes through.
    if (effect_on(EFFECT_DIFFUSE_TRANSMISSION)) {
        DiffuseTransmission through = eval_diffuse_transmission(s.material, triangle, b1, b2);
        bsdf = with_diffuse_transmission(bsdf, through.factor, through.color);
    }
    // Sheen (KHR_materials_sheen) over the base, about its shading normal.
    if (effect_on(EFFECT_SHEEN)) {
        SheenLayer sheen = eval_sheen_layer(s.material, triangle, b1, b2);
        bsdf = with_sheen(bsdf, sheen.color, sheen.roughness);
    }
    // Clear coat (KHR_materials_clearcoat) over all of it, about its own normal on the viewer's side.
    if (effect_on(EFFECT_CLEARCOAT)) {
        ClearcoatLayer coat = eval_clearcoat_layer(s.material, triangle, b1, b2);
        if (coat.weight > 0.0f) {
            vec3 nc = front ? s.nc : -s.nc;
            if (dot(nc, wo) <= 0.0f) nc = ng;
            if (effect_on(EFFECT_CLEARCOAT_NORMAL_TEXTURE)) nc = keep_reflection_above_surface(nc, ng, wo);
            bsdf = with_clearcoat(bsdf, coat.weight, coat.roughness, to_local(frame, nc));
        }
    }
    return bsdf;
}
#endif
