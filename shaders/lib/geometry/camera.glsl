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

// film: position in pixels, (0,0) = top-left corner of the image; lens_u: the aperture's two numbers (thin lens);
// time: when in the shutter, 0..1 (motion blur).
CameraRay make_camera_ray(vec2 film, vec2 lens_u, float time) {
    float ndc_x = 2.0f * film.x / float(params.width) - 1.0f;
    float ndc_y = 1.0f - 2.0f * film.y / float(params.height);
    vec3 right = params.camera_right.xyz;
    vec3 up = params.camera_up.xyz;
    vec3 forward = params.camera_forward.xyz;
    vec3 origin = params.camera_origin.xyz;
    if (effect_on(EFFECT_MOTION_BLUR)) {
        float k = time - 0.5f;
        origin += k * params.camera_motion_translation.xyz;
        vec3 axis = params.camera_motion_rotation.xyz;
        float angle = k * params.camera_motion_rotation.w;
        right = rotate_about_axis(right, axis, angle);
        up = rotate_about_axis(up, axis, angle);
        forward = rotate_about_axis(forward, axis, angle);
    }
    CameraRay ray;
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        ray.origin = origin + ndc_x * right + ndc_y * up;
        ray.dir = forward;
    } else {
        ray.origin = origin;
        ray.dir = normalize(forward + ndc_x * right + ndc_y * up);
    }
    if (effect_on(EFFECT_THIN_LENS)) {
        // The pinhole ray meets the plane in focus at the distance focus_distance along forward.
        vec3 focus = ray.origin + (params.focus_distance / dot(ray.dir, forward)) * ray.dir;
        vec2 lens = params.lens_radius * sample_aperture(lens_u, params.aperture_blades, params.aperture_rotation);
        ray.origin += lens.x * normalize(right) + lens.y * normalize(up);
        ray.dir = normalize(focus - ray.origin);
    }
    return ray;
}
#endif
