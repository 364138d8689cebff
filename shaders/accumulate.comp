// Stage "accumulate": adds the wave's finished paths to the film, one invocation per pixel. The sums are fixed point
// (lib/core/film.glsl): each sample's radiance is rounded once to 2^-FILM_FRACTION_BITS and then added exactly, so the
// film holds the same bits whatever the split of the samples into waves, resumed runs or merged parts. Non-finite
// radiance, and radiance too large for the film (|L| >= 2^FILM_MAX_LOG2), is counted, then dropped.
// With `--aov` it also sums the paths' AOVs into aov_film (lib/core/aov.glsl), in the same fixed point.
// Reads: paths[].radiance, path_aovs, push (wave ranges), pixel_list and path_work (`--adaptive`). Writes: film,
// aov_film, pixel_work (`--adaptive`), counters.nonfinite_samples.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/film.glsl"
#include "lib/core/queue.glsl"
#include "lib/core/techniques.glsl"
#include "lib/core/aov.glsl"
#include "lib/core/wave_pixels.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

uvec4 load_words(uint w[FILM_WORDS]) { return uvec4(w[0], w[1], w[2], w[3]); }

// sum + radiance; false when the radiance (or, as plain float sums, the new sum) cannot be held.
bool add_sample(inout uvec4 sum, float radiance) {
    if (is_fixed_nan(sum)) return true;  // stays NaN, as a float sum would
    if (!FH_TECHNIQUE_ON(TECHNIQUE_EXACT_FILM)) {
        // Plain float sums, to show what exact sums buy: the running sum is rounded to a float at every sample.
        float rounded = decode_fixed(sum) + radiance;
        return encode_fixed(rounded, sum);
    }
    uvec4 value;
    if (!encode_fixed(radiance, value)) return false;
    sum = add_fixed(sum, value);
    return true;
}

// Adds the wave's AOVs of one pixel: a value the fixed point cannot hold (not finite, or too large) adds nothing.
void add_to(inout uint words[FILM_WORDS], float value) {
    uvec4 sum = load_words(words), v;
    if (!encode_fixed(value, v)) return;
    sum = add_fixed(sum, v);
    for (uint w = 0u; w < FILM_WORDS; ++w) words[w] = sum[w];
}

void accumulate_aovs(uint pixel, uint j) {
    AovPixel a = aov_film[pixel];
    for (uint s = 0u; s < push.sample_count; ++s) {
        PathAov p = load_path_aov(s * push.pixel_count + j);
        add_to(a.albedo_r, p.albedo_r);
        add_to(a.albedo_g, p.albedo_g);
        add_to(a.albedo_b, p.albedo_b);
        add_to(a.normal_x, p.normal_x);
        add_to(a.normal_y, p.normal_y);
        add_to(a.normal_z, p.normal_z);
        add_to(a.depth, p.depth);
        if ((p.flags & AOV_HIT) != 0u) a.hit_count += 1u;
    }
    aov_film[pixel] = a;
}

void main() {
    uint j = gl_GlobalInvocationID.x;
    if (j >= push.pixel_count) return;
    uint pixel = wave_film_pixel(j);
    FilmPixel f = film[pixel];
    uvec4 sum_r = load_words(f.sum_r), sum_g = load_words(f.sum_g), sum_b = load_words(f.sum_b);
    uint nonfinite = 0u, work = 0u;
    for (uint s = 0u; s < push.sample_count; ++s) {
        uint path = s * push.pixel_count + j;
        if (pixel_list_on) work += path_work[path];
        PathState state = load_path_state(path);
        vec3 radiance = vec3(state.radiance_r, state.radiance_g, state.radiance_b);
        bool finite = !(any(isnan(radiance)) || any(isinf(radiance)));
        uvec4 r = sum_r, g = sum_g, b = sum_b;
        bool held = finite && add_sample(r, radiance.r) && add_sample(g, radiance.g) && add_sample(b, radiance.b);
        if (!held) {
            nonfinite += 1u;
            if (FH_TECHNIQUE_ON(TECHNIQUE_FINITE_GUARD)) continue;
            // Guard off: what a float film does with it, a sum that stays NaN.
            r = g = b = FIXED_NAN;
        }
        sum_r = r;
        sum_g = g;
        sum_b = b;
    }
    for (uint w = 0u; w < FILM_WORDS; ++w) {
        f.sum_r[w] = sum_r[w];
        f.sum_g[w] = sum_g[w];
        f.sum_b[w] = sum_b[w];
    }
    f.sample_count += push.sample_count;
    film[pixel] = f;
    if (aovs_on) accumulate_aovs(pixel, j);
    if (pixel_list_on) pixel_work[pixel] += work;
    COUNT_IN_SUBGROUP(counters.nonfinite_samples, nonfinite);
}
