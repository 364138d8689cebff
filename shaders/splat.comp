// Stage "splat" (`--integrator light` and `bdpt`): visibility of every camera connection in the shadow queue; an
// unoccluded one adds its contribution to its film pixel (the item's `path` word), or where the splat lands by film
// position (lib/integrator/light_tracing.glsl splats_by_path: the `path` word is the light subpath's, whose time places
// the camera) to the pixel it falls in or, with the Gaussian filter, to every pixel whose filter reaches it, weighted
// by the filter's density. Several subpaths reach one pixel at once, so the
// sums are added with integer atomics, word by word with the carries passed up: integer addition is associative, so
// the film holds the same bits in whatever order the splats land (deterministic, as the accumulate stage's sums are).
// Non-finite or too large contributions are counted and dropped. Reads: shadow_rays, counters.shadow_count_active, BVH.
// Writes: film sums, counters.nonfinite_samples, counters.traced_shadow_rays.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/core/bindings.glsl"
#include "lib/core/film.glsl"
#include "lib/core/queue.glsl"
#include "lib/geometry/traverse.glsl"
#include "lib/integrator/light_tracing.glsl"
#include "lib/sampling/sampling.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

// words += value (128-bit two's complement, least significant word first), atomically per word; the carry out of
// each word goes into the next. A macro: GLSL cannot pass a buffer member by reference.
#define ATOMIC_ADD_FIXED(words, value)                                   \
    {                                                                    \
        uint carry_ = 0u;                                                \
        for (uint k_ = 0u; k_ < FILM_WORDS; ++k_) {                      \
            uint into_next_;                                             \
            uint add_ = uaddCarry(value[k_], carry_, into_next_);        \
            if (add_ != 0u) {                                            \
                uint old_ = atomicAdd(words[k_], add_);                  \
                uint wrapped_;                                           \
                uaddCarry(old_, add_, wrapped_);                         \
                into_next_ += wrapped_;                                  \
            }                                                            \
            carry_ = into_next_;                                         \
        }                                                                \
    }

// Adds contrib to film pixel `pixel`; false (and nothing added) where it is not finite or too large for the film.
bool add_to_film(uint pixel, vec3 contrib) {
    uvec4 r, g, b;
    bool held = encode_fixed(contrib.r, r) && encode_fixed(contrib.g, g) && encode_fixed(contrib.b, b);
    if (!held) return false;
    ATOMIC_ADD_FIXED(film[pixel].sum_r, r);
    ATOMIC_ADD_FIXED(film[pixel].sum_g, g);
    ATOMIC_ADD_FIXED(film[pixel].sum_b, b);
    return true;
}

// A splat that lands by film position: the pixel it falls in (box filter), or every film pixel whose Gaussian reaches
// it, each weighted by the filter's density there. False where a share was not finite or too large.
bool add_at_film_position(vec2 position, vec3 contrib) {
    if (params.filter_type != FILTER_GAUSSIAN) {
        uint pixel;
        return !find_film_pixel(position, pixel) || add_to_film(pixel, contrib);
    }
    float r = params.filter_radius;
    // Pixel x's centre is x + 0.5: the columns and rows within r of the position, inside the film.
    ivec2 lo = max(ivec2(ceil(position - vec2(r + 0.5f))), ivec2(params.crop_x, params.crop_y));
    ivec2 hi = min(ivec2(floor(position + vec2(r - 0.5f))),
                   ivec2(params.crop_x + params.film_width, params.crop_y + params.film_height) - ivec2(1));
    bool held = true;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            float weight = gaussian_filter_density(position - vec2(x, y) - vec2(0.5f), r);
            if (!(weight > 0.0f)) continue;
            uint pixel = uint(y - int(params.crop_y)) * params.film_width + uint(x - int(params.crop_x));
            held = add_to_film(pixel, contrib * weight) && held;
        }
    return held;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters.shadow_count_active) return;
    ShadowRayItem s = load_shadow_ray(i);
    vec3 contrib = vec3(s.contrib_r, s.contrib_g, s.contrib_b);
    if (all(equal(contrib, vec3(0.0f)))) return;  // an empty slot (light_generate)
    uvec4 r, g, b;
    bool finite = encode_fixed(contrib.r, r) && encode_fixed(contrib.g, g) && encode_fixed(contrib.b, b);
    vec2 position = vec2(0.0f);  // on the film, in pixels (splats_by_path)
    bool on_film = !splats_by_path() || find_splat_film_position(s, position);
    COUNT_TRUE_IN_SUBGROUP(counters.nonfinite_samples, !finite);
    if (!finite || !on_film) return;
    // Stochastic alpha keys on the connection itself (its pixel and origin): the same decisions every run.
    uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(s.path ^ pcg_hash(floatBitsToUint(s.origin_x) ^ 0x5b1a7e5u))
                                              : 0u;
    TraceHit hit = trace_ray(vec3(s.origin_x, s.origin_y, s.origin_z), vec3(s.dir_x, s.dir_y, s.dir_z), s.t_max, true,
                             s.origin_triangle, alpha_seed, splats_by_path() ? load_path_time(s.path) : 0.5f);
    COUNT_TRUE_IN_SUBGROUP(counters.traced_shadow_rays, true);
    if (hit.triangle != INVALID_INDEX) return;
    if (!splats_by_path()) {
        ATOMIC_ADD_FIXED(film[s.path].sum_r, r);
        ATOMIC_ADD_FIXED(film[s.path].sum_g, g);
        ATOMIC_ADD_FIXED(film[s.path].sum_b, b);
        return;
    }
    bool held = add_at_film_position(position, contrib);
    COUNT_TRUE_IN_SUBGROUP(counters.nonfinite_samples, !held);
}
