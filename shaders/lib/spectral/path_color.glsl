// The colour a path carries through the shade stage, as a vec4: linear Rec.709 in x, y, z (w unused) or, with
// EFFECT_SPECTRAL, its values at the path's four wavelengths (spectrum.glsl). The BSDF, the lights, the environment
// and the media stay RGB; these helpers turn their colours into the path's and the path's into the film's RGB. For
// an RGB render they are the identity on x, y, z, so its arithmetic (and its bits) are those of a vec3 throughput.
#ifndef FH_PATH_COLOR_GLSL
#define FH_PATH_COLOR_GLSL
#include "lib/core/effects.glsl"
#include "lib/spectral/spectrum.glsl"

vec4 lift_color(SpectralFrame f, vec3 c) { return effect_on(EFFECT_SPECTRAL) ? upsample_rgb(f, c) : vec4(c, 0.0f); }

vec3 film_color(SpectralFrame f, vec4 v) { return effect_on(EFFECT_SPECTRAL) ? integrate_film(f, v) : v.xyz; }

float max_path_component(vec4 v) {
    float m = max(v.x, max(v.y, v.z));
    return effect_on(EFFECT_SPECTRAL) ? max(m, v.w) : m;
}
#endif
