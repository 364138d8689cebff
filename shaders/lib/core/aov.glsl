// The AOVs (`--aov`, SPEC_AOVS): what a camera path's first hits show, for denoisers and compositing, beside the
// beauty image and without changing it. shade records per path (layout.h PathAov): at the first hit its distance, at
// the first non-specular hit the surface's base colour and shading normal, looking through smooth mirrors and glass as
// Intel Open Image Denoise advises; accumulate sums them per pixel in the film's fixed point (layout.h AovPixel).
// Without `--aov` none of it is compiled in. GLSL only.
#ifndef FH_AOV_GLSL
#define FH_AOV_GLSL

layout(constant_id = SPEC_AOVS) const bool aovs_on = false;

PathAov no_aov() {
    PathAov a;
    a.albedo_r = a.albedo_g = a.albedo_b = a.depth = 0.0f;
    a.normal_x = a.normal_y = a.normal_z = 0.0f;
    a.flags = 0u;
    return a;
}

#ifdef FH_BSDF_GLSL
// A surface the AOVs look through: no diffuse or sheen part, and every GGX lobe at most AOV_SPECULAR_ALPHA.
bool aovs_see_through(BsdfParams p) {
    bool diffuse = (1.0f - p.metallic) * (1.0f - p.transmission) > 0.0f || max_value(p.sheen_color) > 0.0f;
    bool rough = p.alpha > AOV_SPECULAR_ALPHA || (p.clearcoat > 0.0f && p.clearcoat_alpha > AOV_SPECULAR_ALPHA);
    return !diffuse && !rough;
}
#endif

// A path's record, two uvec4 (layout.h PathAov, field by field): on lavapipe a struct is loaded and stored a word at a
// time, each a loop over the lanes, a uvec4 at once.
PathAov load_path_aov(uint path) {
    uvec4 a = path_aov_words[2u * path], b = path_aov_words[2u * path + 1u];
    PathAov p;
    p.albedo_r = uintBitsToFloat(a.x);
    p.albedo_g = uintBitsToFloat(a.y);
    p.albedo_b = uintBitsToFloat(a.z);
    p.depth = uintBitsToFloat(a.w);
    p.normal_x = uintBitsToFloat(b.x);
    p.normal_y = uintBitsToFloat(b.y);
    p.normal_z = uintBitsToFloat(b.z);
    p.flags = b.w;
    return p;
}

void store_path_aov(uint path, PathAov p) {
    path_aov_words[2u * path] = uvec4(floatBitsToUint(p.albedo_r), floatBitsToUint(p.albedo_g),
                                      floatBitsToUint(p.albedo_b), floatBitsToUint(p.depth));
    path_aov_words[2u * path + 1u] = uvec4(floatBitsToUint(p.normal_x), floatBitsToUint(p.normal_y),
                                           floatBitsToUint(p.normal_z), p.flags);
}

// The path's AOVs at the vertex its ray `depth` reached: a hit at depth 0 sets the distance; the first hit that is not
// seen through sets albedo and normal. A path starts afresh at depth 0 (its slot served another path before).
void record_aovs(uint path, uint depth, bool hit, float t, bool see_through, vec3 albedo, vec3 normal) {
    PathAov a = no_aov();
    if (depth != 0u) {
        a = load_path_aov(path);
        if ((a.flags & AOV_CAPTURED) != 0u) return;
    }
    bool changed = depth == 0u;
    if (hit && depth == 0u) {
        a.depth = t;
        a.flags |= AOV_HIT;
    }
    if (hit && !see_through) {
        a.albedo_r = albedo.r;
        a.albedo_g = albedo.g;
        a.albedo_b = albedo.b;
        a.normal_x = normal.x;
        a.normal_y = normal.y;
        a.normal_z = normal.z;
        a.flags |= AOV_CAPTURED;
        changed = true;
    }
    if (changed) store_path_aov(path, a);
}

#endif
