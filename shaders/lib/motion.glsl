// Motion blur (EFFECT_MOTION_BLUR): every path has a time s in [0, 1] across the shutter (generate.comp draws it,
// BINDING_PATH_TIMES keeps it), and the instances that move are placed where they are at that time. Their
// transform is interpolated linearly between shutter open and close, element by element (Embree's linear
// instance motion): every point of the mesh moves along a straight segment, so the union of the instance's boxes
// at open and close bounds it all the shutter long, and a translation is exact. A rotation is followed by its
// chord: halfway through a turn of angle a the mesh is scaled by cos(a / 2) across the turn (0.4% for 10 degrees).
// Without the effect, nothing reads a time and every instance stands where it is at the shutter's centre.
#ifndef FH_MOTION_GLSL
#define FH_MOTION_GLSL
#include "effects.glsl"
#include "instance.glsl"

// The time of path `path` in the shutter (0: open, 1: close); the centre without motion blur.
float load_path_time(uint path) { return effect_on(EFFECT_MOTION_BLUR) ? path_times[path] : 0.5f; }

// The instance placed at shutter time `time` (Instance.motion): its render_from_object rows moved, and their
// inverse computed again. An instance that stands still comes back as it is.
Instance move_instance(Instance inst, float time) {
    if (!effect_on(EFFECT_MOTION_BLUR) || inst.motion == INVALID_INDEX) return inst;
    Instance motion = load_instance(inst.motion);
    float k = time - 0.5f;
    inst.render_from_object_0 += k * motion.render_from_object_0;
    inst.render_from_object_1 += k * motion.render_from_object_1;
    inst.render_from_object_2 += k * motion.render_from_object_2;
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
