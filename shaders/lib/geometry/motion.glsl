// Motion blur (EFFECT_MOTION_BLUR): every path has a time s in [0, 1] across the shutter (generate.comp draws it,
// BINDING_PATH_TIMES keeps it), and the instances that move are placed where they are at that time. The shutter is
// cut into FrameParams.motion_segments equal parts (the loader doubles them until no node turns more than 5 degrees
// in one), the transform is keyed at their ends, and within a part it is interpolated linearly, element by element
// (Embree's linear instance motion): every point of the mesh moves along straight segments, so the union of the
// instance's boxes at the keys bounds it all the shutter long, and a translation is exact. A turn is followed by
// chords: halfway through a part that turns by a the mesh is scaled by cos(a / 2) across the turn (0.1% at 5 degrees).
// Without the effect, nothing reads a time and every instance stands where it is at the shutter's centre.
#ifndef FH_MOTION_GLSL
#define FH_MOTION_GLSL
#include "lib/core/effects.glsl"
#include "lib/geometry/instance.glsl"

// The time of path `path` in the shutter (0: open, 1: close); the centre without motion blur.
float load_path_time(uint path) { return effect_on(EFFECT_MOTION_BLUR) ? path_times[path] : 0.5f; }

// The instance placed at shutter time `time` (Instance.motion): its render_from_object rows interpolated between the
// two keys around `time`, and their inverse computed again. An instance that stands still comes back as it is.
Instance move_instance(Instance inst, float time) {
    if (!effect_on(EFFECT_MOTION_BLUR) || inst.motion == INVALID_INDEX) return inst;
    float x = time * float(params.motion_segments);
    uint k = min(uint(x), params.motion_segments - 1u);
    float f = x - float(k);
    Instance a = load_instance(inst.motion + k);
    Instance b = load_instance(inst.motion + k + 1u);
    inst.render_from_object_0 = mix(a.render_from_object_0, b.render_from_object_0, f);
    inst.render_from_object_1 = mix(a.render_from_object_1, b.render_from_object_1, f);
    inst.render_from_object_2 = mix(a.render_from_object_2, b.render_from_object_2, f);
    // mat3 takes columns: this is the transpose of the linear part, so its inverse's columns are the rows of the
    // linear part's inverse.
    mat3 rows_inverse = inverse(mat3(inst.render_from_object_0.xyz, inst.render_from_object_1.xyz,
                                     inst.render_from_object_2.xyz));
    vec3 t = vec3(inst.render_from_object_0.w, inst.render_from_object_1.w, inst.render_from_object_2.w);
    inst.object_from_render_0 = vec4(rows_inverse[0], -dot(rows_inverse[0], t));
    inst.object_from_render_1 = vec4(rows_inverse[1], -dot(rows_inverse[1], t));
    inst.object_from_render_2 = vec4(rows_inverse[2], -dot(rows_inverse[2], t));
    return inst;
}
#endif
