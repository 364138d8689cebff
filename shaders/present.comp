// Stage "present" (viewer only, not part of the bounce loop): turns the film's mean radiance into display
// texels, the same display path as engine/io/tone_curve.cpp: linear * 2^EV -> tone curve -> sRGB OETF -> 8 bit.
// Reads: film (fixed-point sums and sample counts). Writes: pixels (one packed texel per pixel).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "shared/layout.h"
#include "shared/present.h"
#include "lib/core/film.glsl"

layout(local_size_x = PRESENT_WORKGROUP_SIZE) in;
layout(std430, binding = PRESENT_BINDING_FILM) readonly buffer FilmBuffer { FilmPixel film[]; };
layout(std430, binding = PRESENT_BINDING_PIXELS) writeonly buffer PixelBuffer { uint pixels[]; };
layout(push_constant) uniform Push { PresentPush push; };

float tone(float x) {
    if (!(x > 0.0f)) return 0.0f;  // NaN, zero and negatives
    if (push.tone_curve == PRESENT_TONE_CLAMP) return min(x, 1.0f);
    if (x > 1e4f) return 1.0f;
    // Narkowicz 2016 fit of the ACES filmic curve.
    return clamp(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

float encode(float v) {
    v = clamp(v, 0.0f, 1.0f);
    if ((push.flags & PRESENT_ENCODE_SRGB) == 0u) return v;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * pow(v, 1.0f / 2.4f) - 0.055f;
}

void main() {
    uint pixel = gl_GlobalInvocationID.x;
    if (pixel >= push.width * push.height) return;
    FilmPixel f = film[pixel];
    float n = float(max(f.sample_count, 1u));
    vec3 radiance = vec3(decode_fixed(uvec4(f.sum_r[0], f.sum_r[1], f.sum_r[2], f.sum_r[3])),
                         decode_fixed(uvec4(f.sum_g[0], f.sum_g[1], f.sum_g[2], f.sum_g[3])),
                         decode_fixed(uvec4(f.sum_b[0], f.sum_b[1], f.sum_b[2], f.sum_b[3]))) / n;
    vec3 c = radiance * push.exposure_scale;
    uvec3 code = uvec3(round(vec3(encode(tone(c.r)), encode(tone(c.g)), encode(tone(c.b))) * 255.0f));
    if ((push.flags & PRESENT_BGRA) != 0u) code = code.bgr;
    pixels[pixel] = code.r | (code.g << 8u) | (code.b << 16u) | (255u << 24u);
}
