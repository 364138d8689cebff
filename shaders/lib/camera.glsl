// Camera rays for a film position: perspective (pinhole, glTF yfov) and orthographic (glTF xmag/ymag).
#ifndef FH_CAMERA_GLSL
#define FH_CAMERA_GLSL

struct CameraRay {
    vec3 origin;
    vec3 dir;  // unit length
};

// film: position in pixels, (0,0) = top-left corner of the image.
CameraRay make_camera_ray(vec2 film) {
    float ndc_x = 2.0f * film.x / float(params.width) - 1.0f;
    float ndc_y = 1.0f - 2.0f * film.y / float(params.height);
    vec3 right = params.camera_right.xyz;
    vec3 up = params.camera_up.xyz;
    vec3 forward = params.camera_forward.xyz;
    CameraRay ray;
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        ray.origin = params.camera_origin.xyz + ndc_x * right + ndc_y * up;
        ray.dir = forward;
    } else {
        ray.origin = params.camera_origin.xyz;
        ray.dir = normalize(forward + ndc_x * right + ndc_y * up);
    }
    return ray;
}
#endif
