// The random numbers a path's stages consume, from the sampler the render asks for (`--sampler`, specialization
// constant SPEC_SAMPLER): independent (the path's PCG stream, lib/sampling/rng.glsl) or Owen-scrambled Sobol' (lib/sampling/sobol.glsl),
// one 2D or 1D Sobol' dimension per decision: the camera's film position (2D), wavelength (1D), lens (2D) and shutter
// time (1D), then per vertex
// (depth d) the light's point (2D), which light (1D), Russian roulette (1D), the BSDF's direction (2D) and lobe (1D).
// Both are deterministic per (pixel, sample index, seed). GLSL only (inout).
#ifndef FH_PATH_SAMPLER_GLSL
#define FH_PATH_SAMPLER_GLSL
#include "lib/core/effects.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/sampling/sobol.glsl"
#include "lib/core/wave_pixels.glsl"

layout(constant_id = SPEC_SAMPLER) const uint path_sampler = SAMPLER_INDEPENDENT;

// Where path `path` of the current wave sits: its pixel in the whole image (a cropped film's pixel p is the image's
// pixel at crop offset + p; FrameParams) and its sample index (generate.comp's sample-major order). Both decide its
// random numbers, so a pixel gets the same samples with or without a crop, and with or without `--adaptive`.
uint path_pixel(uint path) {
    uint film_pixel = wave_film_pixel(path % push.pixel_count);
    return (params.crop_y + film_pixel / params.film_width) * params.width + params.crop_x + film_pixel % params.film_width;
}
uint path_sample_index(uint path) { return push.sample_begin + path / push.pixel_count; }

// The camera's numbers. Independent: drawn from `rng` in the order film, wavelength (EFFECT_SPECTRAL), lens
// (EFFECT_THIN_LENS), time (EFFECT_MOTION_BLUR), so a render without those draws what it drew before they existed.
// Sobol' dimension numbers (sobol_seed): the camera's, then SOBOL_VERTEX_DIMENSIONS per vertex.
const uint SOBOL_FILM = 0u;
const uint SOBOL_WAVELENGTH = 1u;
const uint SOBOL_LENS = 2u;
const uint SOBOL_TIME = 3u;
const uint SOBOL_CAMERA_DIMENSIONS = 4u;
const uint SOBOL_LIGHT_POINT = 0u;
const uint SOBOL_LIGHT_PICK = 1u;
const uint SOBOL_ROULETTE = 2u;
const uint SOBOL_BSDF_DIRECTION = 3u;
const uint SOBOL_BSDF_LOBE = 4u;
const uint SOBOL_VERTEX_DIMENSIONS = 5u;

struct CameraSamples {
    vec2 film;         // where in the pixel (then warped by the pixel filter)
    float wavelength;  // the hero wavelength's u (EFFECT_SPECTRAL; else 0)
    vec2 lens;         // where on the aperture (EFFECT_THIN_LENS; else 0)
    float time;        // when in the shutter, 0..1 (EFFECT_MOTION_BLUR; else its centre, 0.5)
};

CameraSamples draw_own_camera_samples(uint path, inout uint rng) {
    CameraSamples c;
    c.wavelength = 0.0f;
    c.lens = vec2(0.0f);
    c.time = 0.5f;
    if (path_sampler == SAMPLER_SOBOL) {
        uint pixel = path_pixel(path);
        uint sample_index = path_sample_index(path);
        c.film = sample_sobol_2d(sample_index, sobol_seed(pixel, params.seed, SOBOL_FILM));
        if (effect_on(EFFECT_SPECTRAL))
            c.wavelength = sample_sobol_1d(sample_index, sobol_seed(pixel, params.seed, SOBOL_WAVELENGTH));
        if (effect_on(EFFECT_THIN_LENS))
            c.lens = sample_sobol_2d(sample_index, sobol_seed(pixel, params.seed, SOBOL_LENS));
        if (effect_on(EFFECT_MOTION_BLUR))
            c.time = sample_sobol_1d(sample_index, sobol_seed(pixel, params.seed, SOBOL_TIME));
        return c;
    }
    c.film.x = next_float(rng);
    c.film.y = next_float(rng);
    if (effect_on(EFFECT_SPECTRAL)) c.wavelength = next_float(rng);
    if (effect_on(EFFECT_THIN_LENS)) {
        c.lens.x = next_float(rng);
        c.lens.y = next_float(rng);
    }
    if (effect_on(EFFECT_MOTION_BLUR)) c.time = next_float(rng);
    return c;
}

// Vertex merging joins a camera vertex to the light vertices of every path in its wave, which must share its shutter
// time and wavelengths: with motion blur or dispersion a VCM wave holds one sample index (Renderer), and these two
// numbers are drawn per sample index, the same for every pixel (an Owen-scrambled Sobol' sequence over the sample
// indices, whichever sampler the render uses). Each pixel still sees them stratified over its samples.
const uint SHARED_BY_PIXELS = 0xffffffffu;  // sobol_seed's pixel for numbers no pixel owns
bool wave_shares_time_and_wavelengths() {
    return vcm && (effect_on(EFFECT_SPECTRAL) || effect_on(EFFECT_MOTION_BLUR));
}
void share_time_and_wavelengths(uint path, inout CameraSamples c) {
    uint sample_index = path_sample_index(path);
    if (effect_on(EFFECT_SPECTRAL))
        c.wavelength = sample_sobol_1d(sample_index, sobol_seed(SHARED_BY_PIXELS, params.seed, SOBOL_WAVELENGTH));
    if (effect_on(EFFECT_MOTION_BLUR))
        c.time = sample_sobol_1d(sample_index, sobol_seed(SHARED_BY_PIXELS, params.seed, SOBOL_TIME));
}

CameraSamples draw_camera_samples(uint path, inout uint rng) {
    CameraSamples c = draw_own_camera_samples(path, rng);
    if (wave_shares_time_and_wavelengths()) share_time_and_wavelengths(path, c);
    return c;
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
        uint first = SOBOL_CAMERA_DIMENSIONS + SOBOL_VERTEX_DIMENSIONS * depth;
        s.light = sample_sobol_2d(sample_index, sobol_seed(pixel, params.seed, first + SOBOL_LIGHT_POINT));
        s.pick = sample_sobol_1d(sample_index, sobol_seed(pixel, params.seed, first + SOBOL_LIGHT_PICK));
        s.roulette = sample_sobol_1d(sample_index, sobol_seed(pixel, params.seed, first + SOBOL_ROULETTE));
        s.bsdf.yz = sample_sobol_2d(sample_index, sobol_seed(pixel, params.seed, first + SOBOL_BSDF_DIRECTION));
        s.bsdf.x = sample_sobol_1d(sample_index, sobol_seed(pixel, params.seed, first + SOBOL_BSDF_LOBE));
        return s;
    }
    s.pick = next_float(rng);
    s.light = vec2(next_float(rng), next_float(rng));
    s.bsdf = vec3(next_float(rng), next_float(rng), next_float(rng));
    s.roulette = next_float(rng);
    return s;
}
#endif
