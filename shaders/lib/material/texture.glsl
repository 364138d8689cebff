// Texture reads of the stages: the one place a material slot is sampled (nearest or bilinear, decoded to linear
// before filtering) and where triangle texture coordinates and vertex colours are interpolated.
#ifndef FH_TEXTURE_GLSL
#define FH_TEXTURE_GLSL
#include "lib/material/texture_address.glsl"

// The images' RGBA8 texels, four to a texel of the RGBA32UI texel buffer (layout.h BINDING_TEXELS).
layout(binding = BINDING_TEXELS) uniform usamplerBuffer image_texels;

uint load_image_texel(uint index) { return texelFetch(image_texels, int(index >> 2u))[index & 3u]; }

// Both texture coordinate sets at barycentrics (b1, b2) of a triangle.
struct Texcoords {
    vec2 uv0;
    vec2 uv1;
};

Texcoords interpolate_texcoords(uint triangle, float b1, float b2) {
    TriangleAttributes a = load_triangle_attributes(triangle);
    float b0 = 1.0f - b1 - b2;
    Texcoords t;
    t.uv0 = b0 * a.uv0_c01.xy + b1 * a.uv0_c01.zw + b2 * a.uv0_c2_uv1_c0.xy;
    t.uv1 = b0 * a.uv0_c2_uv1_c0.zw + b1 * a.uv1_c12.xy + b2 * a.uv1_c12.zw;
    return t;
}

vec4 unpack_half4(uint rg, uint ba) { return vec4(unpackHalf2x16(rg), unpackHalf2x16(ba)); }

// Written as c0 + b1 (c1 - c0) + b2 (c2 - c0): equal corners give exactly their colour (white stays 1, so forcing
// the effect on for a scene without COLOR_0 changes no bit).
vec4 interpolate_color(uint triangle, float b1, float b2) {
    TriangleAttributes a = load_triangle_attributes(triangle);
    vec4 c0 = unpack_half4(a.color0_rg, a.color0_ba);
    return c0 + b1 * (unpack_half4(a.color1_rg, a.color1_ba) - c0) + b2 * (unpack_half4(a.color2_rg, a.color2_ba) - c0);
}

// Interpolated TANGENT (w = bitangent sign), or w = 0 when the mesh has none.
vec4 interpolate_tangent(uint triangle, float b1, float b2) {
    TriangleAttributes a = load_triangle_attributes(triangle);
    float b0 = 1.0f - b1 - b2;
    vec4 t0 = unpack_half4(a.tangent0_xy, a.tangent0_zw);
    vec4 t = b0 * t0 + b1 * unpack_half4(a.tangent1_xy, a.tangent1_zw) + b2 * unpack_half4(a.tangent2_xy, a.tangent2_zw);
    t.w = t0.w;  // the sign is the same at every corner of a well-formed mesh
    return t;
}

uint load_texel(TextureImage image, int x, int y) {
    return load_image_texel(image.texel_offset + uint(y) * image.width + uint(x));
}

// Material slot `slot_index` at the hit's texture coordinates: linear RGBA (colour slots sRGB-decoded).
vec4 sample_texture(uint slot_index, Texcoords tc) {
    TextureSlot slot = load_texture_slot(slot_index);
    vec2 uv = transform_texcoord(slot, (slot.addressing & SAMPLER_TEXCOORD_1) != 0u ? tc.uv1 : tc.uv0);
    TextureImage image = load_texture_image(slot.image);
    uint wrap_s = slot.addressing & 3u;
    uint wrap_t = (slot.addressing >> 2u) & 3u;
    bool srgb = (slot.addressing & SAMPLER_SRGB) != 0u;
    int w = int(image.width);
    int h = int(image.height);
    float x = reduce_texcoord(uv.x, wrap_s) * float(w);
    float y = reduce_texcoord(uv.y, wrap_t) * float(h);
    if ((slot.addressing & SAMPLER_NEAREST) != 0u) {
        int i = wrap_texel(int(floor(x)), w, wrap_s);
        int j = wrap_texel(int(floor(y)), h, wrap_t);
        return decode_texel(load_texel(image, i, j), srgb);
    }
    // Bilinear between the four texel centres around (x, y).
    x -= 0.5f;
    y -= 0.5f;
    float fx = floor(x);
    float fy = floor(y);
    vec2 f = vec2(x - fx, y - fy);
    int i0 = wrap_texel(int(fx), w, wrap_s);
    int i1 = wrap_texel(int(fx) + 1, w, wrap_s);
    int j0 = wrap_texel(int(fy), h, wrap_t);
    int j1 = wrap_texel(int(fy) + 1, h, wrap_t);
    vec4 top = mix(decode_texel(load_texel(image, i0, j0), srgb), decode_texel(load_texel(image, i1, j0), srgb), f.x);
    vec4 bottom = mix(decode_texel(load_texel(image, i0, j1), srgb), decode_texel(load_texel(image, i1, j1), srgb), f.x);
    return mix(top, bottom, f.y);
}
#endif
