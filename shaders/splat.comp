// Stage "splat" (`--integrator light`): visibility of every camera connection in the shadow queue; an unoccluded one
// adds its contribution to its film pixel (the item's `path` word). Several subpaths reach one pixel at once, so the
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

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= counters.shadow_count_active) return;
    ShadowRayItem s = load_shadow_ray(i);
    vec3 contrib = vec3(s.contrib_r, s.contrib_g, s.contrib_b);
    if (all(equal(contrib, vec3(0.0f)))) return;  // an empty slot (light_generate)
    uvec4 r, g, b;
    bool held = encode_fixed(contrib.r, r) && encode_fixed(contrib.g, g) && encode_fixed(contrib.b, b);
    COUNT_TRUE_IN_SUBGROUP(counters.nonfinite_samples, !held);
    if (!held) return;
    // Stochastic alpha keys on the connection itself (its pixel and origin): the same decisions every run.
    uint alpha_seed = effect_on(EFFECT_ALPHA) ? pcg_hash(s.path ^ pcg_hash(floatBitsToUint(s.origin_x) ^ 0x5b1a7e5u))
                                              : 0u;
    TraceHit hit = trace_ray(vec3(s.origin_x, s.origin_y, s.origin_z), vec3(s.dir_x, s.dir_y, s.dir_z), s.t_max, true,
                             s.origin_triangle, alpha_seed, 0.5f);
    COUNT_TRUE_IN_SUBGROUP(counters.traced_shadow_rays, true);
    if (hit.triangle != INVALID_INDEX) return;
    ATOMIC_ADD_FIXED(film[s.path].sum_r, r);
    ATOMIC_ADD_FIXED(film[s.path].sum_g, g);
    ATOMIC_ADD_FIXED(film[s.path].sum_b, b);
}
