// Stage "accumulate": adds the wave's finished paths to the film, one invocation per pixel, samples in
// index order (so the sum is deterministic). Kahan-compensated float sums (Kahan 1965); `precise` stops the
// compiler from reassociating them away. Non-finite radiance is counted, then dropped.
// Reads: paths[].radiance, push (wave ranges). Writes: film, counters.nonfinite_samples.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "lib/bindings.glsl"
#include "lib/queue.glsl"
#include "lib/techniques.glsl"

layout(local_size_x = WORKGROUP_SIZE) in;

void main() {
    uint j = gl_GlobalInvocationID.x;
    if (j >= push.pixel_count) return;
    uint pixel = push.pixel_begin + j;
    FilmPixel f = film[pixel];
    precise vec3 sum = vec3(f.sum_r, f.sum_g, f.sum_b);
    precise vec3 comp = vec3(f.comp_r, f.comp_g, f.comp_b);
    uint nonfinite = 0u;
    for (uint s = 0u; s < push.sample_count; ++s) {
        uint path = s * push.pixel_count + j;
        vec3 radiance = vec3(paths[path].radiance_r, paths[path].radiance_g, paths[path].radiance_b);
        if (any(isnan(radiance)) || any(isinf(radiance))) {
            nonfinite += 1u;
            if (FH_TECHNIQUE_ON(TECHNIQUE_FINITE_GUARD)) radiance = vec3(0.0f);
        }
        if (FH_TECHNIQUE_ON(TECHNIQUE_COMPENSATED_FILM)) {
            precise vec3 y = radiance - comp;
            precise vec3 t = sum + y;
            comp = (t - sum) - y;
            sum = t;
        } else {
            sum += radiance;
        }
    }
    f.sum_r = sum.x;
    f.sum_g = sum.y;
    f.sum_b = sum.z;
    f.comp_r = comp.x;
    f.comp_g = comp.y;
    f.comp_b = comp.z;
    f.sample_count += float(push.sample_count);
    film[pixel] = f;
    COUNT_IN_SUBGROUP(counters.nonfinite_samples, nonfinite);
}
