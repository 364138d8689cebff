// The material at a surface point: glTF factors times textures and COLOR_0 (spec 3.9.2), alpha (3.9.4) and
// the normal texture (3.9.3). Each part is compiled only when the scene's effect set asks for it.
#ifndef FH_MATERIAL_GLSL
#define FH_MATERIAL_GLSL
#include "lib/core/effects.glsl"
#include "lib/sampling/rng.glsl"
#include "lib/material/texture.glsl"

// KHR_materials_specular: specularFactor times the specularTexture's A, specularColorFactor times the
// specularColorTexture's RGB (sRGB). A specular-glossiness material (MATERIAL_GLOSSINESS_IN_ALPHA) keeps its
// glossiness in the colour texture's alpha: roughness = 1 - glossinessFactor x A (m.roughness = 1 - glossinessFactor).
Material apply_specular_textures(Material m, Texcoords tc) {
    if (effect2_on(EFFECT2_SPECULAR_TEXTURE) && m.specular_texture != INVALID_INDEX)
        m.specular_color.w *= sample_texture(m.specular_texture, tc).w;
    if (m.specular_color_texture == INVALID_INDEX) return m;
    vec4 t = sample_texture(m.specular_color_texture, tc);
    if (effect2_on(EFFECT2_SPECULAR_TEXTURE)) m.specular_color.xyz *= t.xyz;
    if (effect2_on(EFFECT2_GLOSSINESS_TEXTURE) && (m.flags & MATERIAL_GLOSSINESS_IN_ALPHA) != 0u)
        m.roughness = 1.0f - (1.0f - m.roughness) * t.w;
    return m;
}

// `m` with its factors multiplied by the textures and vertex colour at barycentrics (b1, b2) of `triangle`.
Material resolve_material(Material m, uint triangle, float b1, float b2) {
    if (!effect_on(EFFECT_ATTRIBUTES) && !effect2_on(EFFECT2_ATTRIBUTES)) return m;
    Texcoords tc = interpolate_texcoords(triangle, b1, b2);
    if (effect_on(EFFECT_BASE_COLOR_TEXTURE) && m.base_color_texture != INVALID_INDEX)
        m.base_color *= sample_texture(m.base_color_texture, tc);
    if (effect_on(EFFECT_VERTEX_COLORS)) m.base_color *= interpolate_color(triangle, b1, b2);
    if (effect_on(EFFECT_METALLIC_ROUGHNESS_TEXTURE) && m.metallic_roughness_texture != INVALID_INDEX) {
        vec4 t = sample_texture(m.metallic_roughness_texture, tc);
        m.roughness *= t.y;  // G channel
        m.metallic *= t.z;   // B channel
    }
    if (effect_on(EFFECT_EMISSIVE_TEXTURE) && m.emissive_texture != INVALID_INDEX)
        m.emission.xyz *= sample_texture(m.emissive_texture, tc).xyz;
    if (effect2_on(EFFECT2_SPECULAR_TEXTURE | EFFECT2_GLOSSINESS_TEXTURE)) m = apply_specular_textures(m, tc);
    return m;
}

// Alpha of `m` at the point (factor x base colour texture x COLOR_0).
float eval_alpha(Material m, uint triangle, float b1, float b2) {
    float alpha = m.base_color.w;
    if (effect_on(EFFECT_BASE_COLOR_TEXTURE) && m.base_color_texture != INVALID_INDEX)
        alpha *= sample_texture(m.base_color_texture, interpolate_texcoords(triangle, b1, b2)).w;
    if (effect_on(EFFECT_VERTEX_COLORS)) alpha *= interpolate_color(triangle, b1, b2).w;
    return alpha;
}

// Probability that a ray meets the surface at the point: 1 (OPAQUE), 0 or 1 (MASK: alpha >= cutoff), alpha
// (BLEND: stochastic transparency, an unbiased estimate of alpha-weighted blending).
float eval_coverage(uint triangle, float b1, float b2) {
    Material m = load_material(load_triangle_shading(triangle).material);
    if (m.alpha_mode == ALPHA_OPAQUE) return 1.0f;
    float alpha = eval_alpha(m, triangle, b1, b2);
    if (m.alpha_mode == ALPHA_MASK) return alpha >= m.alpha_cutoff ? 1.0f : 0.0f;
    return clamp(alpha, 0.0f, 1.0f);
}

// Whether the ray with `ray_seed` meets `triangle` at (b1, b2). The decision is a hash of the ray and the
// triangle, so it is the same however often traversal tests the pair, and independent between rays.
bool is_surface_present(uint triangle, float b1, float b2, uint ray_seed) {
    float coverage = eval_coverage(triangle, b1, b2);
    if (coverage >= 1.0f) return true;
    if (coverage <= 0.0f) return false;
    uint h = pcg_hash(ray_seed ^ pcg_hash(load_triangle_positions(triangle).source_index));
    return float(h >> 8u) * (1.0f / 16777216.0f) < coverage;
}

// A layer's two optional textures at the hit (KHR material extensions: a weight or colour and a roughness or
// factor): each slot's texel, or vec4(1) where the slot is INVALID_INDEX (multiplying by it changes no bit). The
// texture coordinates are interpolated only when there is a slot to read.
struct LayerTexels {
    vec4 first;
    vec4 second;
};

LayerTexels sample_layer_textures(uint first_slot, uint second_slot, uint triangle, float b1, float b2) {
    LayerTexels t;
    t.first = vec4(1.0f);
    t.second = vec4(1.0f);
    if (first_slot != INVALID_INDEX || second_slot != INVALID_INDEX) {
        Texcoords tc = interpolate_texcoords(triangle, b1, b2);
        if (first_slot != INVALID_INDEX) t.first = sample_texture(first_slot, tc);
        if (second_slot != INVALID_INDEX) t.second = sample_texture(second_slot, tc);
    }
    return t;
}

// The mesh's tangent frame at a point with unit normal `ns`: the tangent t (unit, orthogonal to ns) and the
// bitangent b = cross(ns, t) x sign, from the interpolated tangent (the file's TANGENT or the loader's MikkTSpace
// ones, engine/scene/gltf/README.md "Textures") or, where a vertex has none (w 0), from the triangle's derivatives of
// texture coordinate set 1 (`set1`) or 0. `valid` is false where neither gives a frame.
struct TangentFrame {
    vec3 t;
    vec3 b;
    bool valid;
};

TangentFrame build_tangent_frame(bool set1, uint triangle, float b1, float b2, vec3 ns) {
    TangentFrame f;
    f.t = vec3(1.0f, 0.0f, 0.0f);
    f.b = vec3(0.0f, 1.0f, 0.0f);
    f.valid = false;
    vec4 tangent = interpolate_tangent(triangle, b1, b2);
    vec3 t = tangent.xyz;
    float sign = tangent.w;
    if (sign == 0.0f) {
        TriangleAttributes a = load_triangle_attributes(triangle);
        vec2 uv0 = set1 ? a.uv0_c2_uv1_c0.zw : a.uv0_c01.xy;
        vec2 uv1 = set1 ? a.uv1_c12.xy : a.uv0_c01.zw;
        vec2 uv2 = set1 ? a.uv1_c12.zw : a.uv0_c2_uv1_c0.xy;
        vec3 dp1 = load_triangle_vertex(triangle, 1u) - load_triangle_vertex(triangle, 0u);
        vec3 dp2 = load_triangle_vertex(triangle, 2u) - load_triangle_vertex(triangle, 0u);
        vec2 duv1 = uv1 - uv0;
        vec2 duv2 = uv2 - uv0;
        float det = duv1.x * duv2.y - duv1.y * duv2.x;
        if (!(abs(det) > 1e-20f)) return f;  // no texture-space frame
        // dp/du and dp/dv. glTF's v runs down the image while tangent space's +Y points up it, so the bitangent
        // is -dp/dv (what MikkTSpace gives for glTF's flipped texture coordinates).
        t = (dp1 * duv2.y - dp2 * duv1.y) / det;
        vec3 b = (dp2 * duv1.x - dp1 * duv2.x) / det;
        sign = dot(cross(ns, t), b) < 0.0f ? 1.0f : -1.0f;
    }
    t -= ns * dot(ns, t);
    float t_len = length(t);
    if (!(t_len > 0.0f) || isinf(t_len)) return f;
    f.t = t / t_len;
    f.b = cross(ns, f.t) * sign;
    f.valid = true;
    return f;
}

// `ns` (the interpolated normal, on the geometric normal's side) with the tangent-space normal texture of
// TextureSlot `slot_index` applied (spec 3.9.3), on the same side.
vec3 apply_normal_map(uint slot_index, uint triangle, float b1, float b2, vec3 ns) {
    TextureSlot slot = load_texture_slot(slot_index);
    TangentFrame f = build_tangent_frame((slot.addressing & SAMPLER_TEXCOORD_1) != 0u, triangle, b1, b2, ns);
    if (!f.valid) return ns;  // leave the normal alone
    vec3 n_ts = sample_texture(slot_index, interpolate_texcoords(triangle, b1, b2)).xyz * 2.0f - 1.0f;
    n_ts.xy *= slot.scale;
    vec3 n = f.t * n_ts.x + f.b * n_ts.y + ns * n_ts.z;
    float n_len = length(n);
    return n_len > 0.0f && !isinf(n_len) ? n / n_len : ns;
}

// The shading normal with the material's normalTexture applied (apply_normal_map).
vec3 apply_normal_texture(Material m, uint triangle, float b1, float b2, vec3 ns) {
    if (!effect_on(EFFECT_NORMAL_TEXTURE) || m.normal_texture == INVALID_INDEX) return ns;
    return apply_normal_map(m.normal_texture, triangle, b1, b2, ns);
}

// A normal-mapped normal can tilt so far that the mirror direction of the viewer falls below the geometric
// surface: a smooth surface then reflects nothing (black patches on smooth, strongly normal-mapped metal). As
// Cycles does (its ensure_valid_specular_reflection), bend the normal towards the geometric one, just enough that
// the mirror direction stays above the surface: here by bisection on n' = normalize(mix(n, ng, s)). ng and n on
// the viewer's side; wo towards the viewer. Not energy conserving in general (engine/scene/gltf/README.md "Textures", normal maps).
vec3 keep_reflection_above_surface(vec3 n, vec3 ng, vec3 wo) {
    float ng_wo = dot(ng, wo);
    float threshold = min(0.9f * ng_wo, 0.01f);
    if (dot(ng, 2.0f * dot(n, wo) * n - wo) >= threshold) return n;
    float lo = 0.0f;
    float hi = 1.0f;
    for (int i = 0; i < 12; ++i) {
        float mid = 0.5f * (lo + hi);
        vec3 m = normalize(mix(n, ng, mid));
        if (dot(ng, 2.0f * dot(m, wo) * m - wo) >= threshold) hi = mid;
        else lo = mid;
    }
    return normalize(mix(n, ng, hi));
}
#endif
