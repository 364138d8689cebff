// Camera rays for a film position: perspective (pinhole, glTF yfov) and orthographic (glTF xmag/ymag), and with
// EFFECT_THIN_LENS a thin lens in front of either (pbrt-v4's model): the ray through the lens centre is the
// pinhole's; a ray from another point of the aperture aims at where that one meets the plane in focus, so the field
// of view stays glTF's and points on that plane stay sharp. With EFFECT_MOTION_BLUR a moving camera is placed at the
// ray's time: its origin moves along a line and its axes turn about a fixed axis at a constant rate, open to close.
#ifndef FH_CAMERA_GLSL
#define FH_CAMERA_GLSL
#include "lib/core/effects.glsl"
#include "lib/sampling/sampling.glsl"

struct CameraRay {
    vec3 origin;
    vec3 dir;  // unit length
};

// v turned by `angle` radians about the unit `axis` (Rodrigues).
vec3 rotate_about_axis(vec3 v, vec3 axis, float angle) {
    float c = cos(angle), s = sin(angle);
    return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0f - c));
}

// The camera's origin and axes (FrameParams.camera_*) at shutter time `time`, 0..1 (motion blur); without it, as they
// are.
struct CameraView {
    vec3 origin;
    vec3 right;    // scaled so that NDC x = 1 maps to it (at unit distance)
    vec3 up;       // likewise for NDC y = 1
    vec3 forward;  // unit
};

CameraView camera_view_at(float time) {
    CameraView v;
    v.right = params.camera_right.xyz;
    v.up = params.camera_up.xyz;
    v.forward = params.camera_forward.xyz;
    v.origin = params.camera_origin.xyz;
    if (effect_on(EFFECT_MOTION_BLUR)) {
        float k = time - 0.5f;
        v.origin += k * params.camera_motion_translation.xyz;
        vec3 axis = params.camera_motion_rotation.xyz;
        float angle = k * params.camera_motion_rotation.w;
        v.right = rotate_about_axis(v.right, axis, angle);
        v.up = rotate_about_axis(v.up, axis, angle);
        v.forward = rotate_about_axis(v.forward, axis, angle);
    }
    return v;
}

// The point of the aperture (EFFECT_THIN_LENS) that lens_u draws, around `centre`, uniformly by area.
vec3 sample_lens_point(CameraView view, vec3 centre, vec2 lens_u) {
    vec2 lens = params.lens_radius * sample_aperture(lens_u, params.aperture_blades, params.aperture_rotation);
    return centre + (lens.x * normalize(view.right) + lens.y * normalize(view.up));
}

// film: position in pixels, (0,0) = top-left corner of the image; lens_u: the aperture's two numbers (thin lens);
// time: when in the shutter, 0..1 (motion blur).
CameraRay make_camera_ray(vec2 film, vec2 lens_u, float time) {
    float ndc_x = 2.0f * film.x / float(params.width) - 1.0f;
    float ndc_y = 1.0f - 2.0f * film.y / float(params.height);
    CameraView view = camera_view_at(time);
    CameraRay ray;
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        ray.origin = view.origin + ndc_x * view.right + ndc_y * view.up;
        ray.dir = view.forward;
    } else {
        ray.origin = view.origin;
        ray.dir = normalize(view.forward + ndc_x * view.right + ndc_y * view.up);
    }
    if (effect_on(EFFECT_THIN_LENS)) {
        // The pinhole ray meets the plane in focus at the distance focus_distance along forward.
        vec3 focus = ray.origin + (params.focus_distance / dot(ray.dir, view.forward)) * ray.dir;
        ray.origin = sample_lens_point(view, ray.origin, lens_u);
        ray.dir = normalize(focus - ray.origin);
    }
    return ray;
}
#endif
