// The random numbers a path's stages consume, from the sampler the render asks for (`--sampler`, specialization
// constant SPEC_SAMPLER): independent (the path's PCG stream, lib/rng.glsl) or Owen-scrambled Sobol' (lib/sobol.glsl),
// whose blocks of four dimensions are: 0 the camera (film position, wavelength), then per vertex (depth d) 1 + 2d the
// light sample (two for the point, the light's pick, Russian roulette) and 2 + 2d the BSDF sample (two for the
// direction, the lobe's pick). Both are deterministic per (pixel, sample index, seed). GLSL only (inout).
#ifndef FH_PATH_SAMPLER_GLSL
#define FH_PATH_SAMPLER_GLSL
#include "effects.glsl"
#include "rng.glsl"
#include "sobol.glsl"

layout(constant_id = SPEC_SAMPLER) const uint path_sampler = SAMPLER_INDEPENDENT;

// Where path `path` of the current wave sits: its pixel and its sample index (generate.comp's sample-major order).
uint path_pixel(uint path) { return push.pixel_begin + path % push.pixel_count; }
uint path_sample_index(uint path) { return push.sample_begin + path / push.pixel_count; }

// The camera's numbers: film offset (xy) and the hero wavelength's u (z). Independent: drawn from `rng` in that order.
vec3 draw_camera_samples(uint path, inout uint rng) {
    if (path_sampler == SAMPLER_SOBOL) {
        vec4 u = sample_sobol_block(path_sample_index(path), sobol_block_seed(path_pixel(path), params.seed, 0u));
        return u.xyz;
    }
    vec3 u;
    u.x = next_float(rng);
    u.y = next_float(rng);
    u.z = effect_on(EFFECT_SPECTRAL) ? next_float(rng) : 0.0f;
    return u;
}

// What one path vertex samples with.
struct VertexSamples {
    float pick;     // which light
    vec2 light;     // where on it
    vec3 bsdf;      // x: which lobe, yz: the direction
    float roulette; // Russian roulette
};

// The numbers of the vertex at depth `depth` (segments traced so far). Independent: drawn from `rng` in the order
// pick, light, bsdf, roulette.
VertexSamples draw_vertex_samples(uint path, uint depth, inout uint rng) {
    VertexSamples s;
    if (path_sampler == SAMPLER_SOBOL) {
        uint pixel = path_pixel(path);
        uint sample_index = path_sample_index(path);
        vec4 light = sample_sobol_block(sample_index, sobol_block_seed(pixel, params.seed, 1u + 2u * depth));
        vec4 bsdf = sample_sobol_block(sample_index, sobol_block_seed(pixel, params.seed, 2u + 2u * depth));
        s.light = light.xy;
        s.pick = light.z;
        s.roulette = light.w;
        s.bsdf = vec3(bsdf.z, bsdf.x, bsdf.y);
        return s;
    }
    s.pick = next_float(rng);
    s.light = vec2(next_float(rng), next_float(rng));
    s.bsdf = vec3(next_float(rng), next_float(rng), next_float(rng));
    s.roulette = next_float(rng);
    return s;
}
#endif
