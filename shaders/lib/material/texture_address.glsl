// Texel addressing shared by the GPU stages and the host (emitter power of textured lights): glTF sampler wrap
// modes, KHR_texture_transform, RGBA8 unpacking and the sRGB transfer function. Shared GLSL/C++ subset.
#ifndef FH_TEXTURE_ADDRESS_GLSL
#define FH_TEXTURE_ADDRESS_GLSL

#ifdef __cplusplus
using fh::gpu::TextureSlot;
using fh::gpu::WRAP_CLAMP_TO_EDGE;
using fh::gpu::WRAP_MIRRORED_REPEAT;
#else
#include "shared/layout.h"
#endif

// KHR_texture_transform: uv' = M (u, v, 1), M's rows in the slot.
vec2 transform_texcoord(TextureSlot slot, vec2 uv) {
    vec2 out_uv;
    out_uv.x = slot.transform_u.x * uv.x + slot.transform_u.y * uv.y + slot.transform_u.z;
    out_uv.y = slot.transform_v.x * uv.x + slot.transform_v.y * uv.y + slot.transform_v.z;
    return out_uv;
}

// A texture coordinate brought into a bounded range with the same texels as before: one period for REPEAT,
// two for MIRRORED_REPEAT, [-1, 2] for CLAMP_TO_EDGE (so that scaling by the size cannot overflow an int).
// NaN reads as 0.
float reduce_texcoord(float u, uint mode) {
    if (isnan(u)) return 0.0f;
    if (mode == WRAP_CLAMP_TO_EDGE) return clamp(u, -1.0f, 2.0f);
    if (mode == WRAP_MIRRORED_REPEAT) return u - 2.0f * floor(0.5f * u);
    return u - floor(u);
}

// Integer texel coordinate i (any int) wrapped into [0, size) as glTF's samplers (OpenGL) define.
int wrap_texel(int i, int size, uint mode) {
    if (mode == WRAP_CLAMP_TO_EDGE) return clamp(i, 0, size - 1);
    if (mode == WRAP_MIRRORED_REPEAT) {
        int period = 2 * size;
        int m = i % period;
        if (m < 0) m += period;
        return m < size ? m : period - 1 - m;
    }
    int m = i % size;
    if (m < 0) m += size;
    return m;
}

// RGBA8 texel (r in the low byte) to [0, 1].
vec4 unpack_texel(uint t) {
    vec4 c;
    c.x = float(t & 255u);
    c.y = float((t >> 8u) & 255u);
    c.z = float((t >> 16u) & 255u);
    c.w = float(t >> 24u);
    return c * (1.0f / 255.0f);
}

// IEC 61966-2-1 sRGB decoding (what a GPU's *_SRGB formats do before filtering).
float srgb_to_linear(float c) {
    return c <= 0.04045f ? c * (1.0f / 12.92f) : pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

vec4 decode_texel(uint t, bool srgb) {
    vec4 c = unpack_texel(t);
    if (srgb) {
        c.x = srgb_to_linear(c.x);
        c.y = srgb_to_linear(c.y);
        c.z = srgb_to_linear(c.z);
    }
    return c;
}
#endif
