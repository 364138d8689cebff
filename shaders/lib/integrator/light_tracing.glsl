// Light tracing (`--integrator light`): the strategies of bidirectional path tracing that join a light subpath to
// the camera directly (t = 1 in Veach 1997's notation), unweighted. A vertex of a light subpath is projected onto the
// film through the pinhole, and what it sends towards the camera becomes a splat on the pixel it lands in
// (splat.comp adds it once a shadow ray finds the way clear).
//
// The pixel's value is the film average of radiance over the pixel (box filter), I = 1 / A_pixel x integral over the
// pixel's part of the image plane at unit distance of L dA. dA = dw / cos^3(theta) on that plane, and dw =
// cos(theta_x) dA_x / d^2 at the surface, so a light subpath that reaches x with throughput beta and sends f towards
// the camera adds beta f cos(theta_x) / (d^2 A_pixel cos^3(theta)) to its pixel. A render traces one light subpath
// per film pixel and sample index, so each splat is also divided by the film's pixel count: the film's
// sum / sample count then estimates I (cf. pbrt-v3's PerspectiveCamera::We, which normalises by the whole film).
#ifndef FH_LIGHT_TRACING_GLSL
#define FH_LIGHT_TRACING_GLSL
#include "lib/geometry/ray_offset.glsl"

struct FilmSplat {
    vec3 to_camera;    // unit direction from the point towards the camera
    float dist;        // distance to the camera
    uint pixel;        // film pixel (row major, a cropped film's own)
    float importance;  // what a unit of radiance sent towards the camera adds to that pixel's sum
    bool valid;        // false: behind the camera, outside the image or outside the crop
};

// The film pixel at normalised device coordinates (make_camera_ray's), if it is on the film (inside the crop).
bool find_film_pixel(float ndc_x, float ndc_y, out uint pixel) {
    pixel = 0u;
    float fx = (ndc_x + 1.0f) * 0.5f * float(params.width);
    float fy = (1.0f - ndc_y) * 0.5f * float(params.height);
    if (!(fx >= 0.0f && fx < float(params.width) && fy >= 0.0f && fy < float(params.height))) return false;
    uint x = min(uint(fx), params.width - 1u), y = min(uint(fy), params.height - 1u);
    if (x < params.crop_x || y < params.crop_y) return false;
    x -= params.crop_x;
    y -= params.crop_y;
    if (x >= params.film_width || y >= params.film_height) return false;
    pixel = y * params.film_width + x;
    return true;
}

// 1 / (a pixel's area on the image plane x the light subpaths per sample index): the importance's constant part.
float film_importance_scale() {
    float pixel_area = 4.0f * length(params.camera_right.xyz) * length(params.camera_up.xyz) /
                       (float(params.width) * float(params.height));
    return 1.0f / (pixel_area * float(params.film_width) * float(params.film_height));
}

FilmSplat make_invalid_splat() {
    FilmSplat s;
    s.to_camera = vec3(0.0f, 0.0f, 1.0f);
    s.dist = 0.0f;
    s.pixel = 0u;
    s.importance = 0.0f;
    s.valid = false;
    return s;
}

// Where direction w (unit, from the camera) is seen on the film of the perspective pinhole camera (the inverse of
// make_camera_ray); the importance is per unit of solid angle there (a light at infinity). An orthographic camera sees
// one direction only: never a sampled one.
FilmSplat project_direction_to_film(vec3 w) {
    FilmSplat s = make_invalid_splat();
    float cos_theta = dot(w, params.camera_forward.xyz);
    if (params.camera_type == CAMERA_ORTHOGRAPHIC || !(cos_theta > 0.0f)) return s;
    vec3 on_plane = w / cos_theta;  // on the image plane at unit distance along forward
    vec3 right = params.camera_right.xyz;
    vec3 up = params.camera_up.xyz;
    s.valid = find_film_pixel(dot(on_plane, right) / dot(right, right), dot(on_plane, up) / dot(up, up), s.pixel);
    s.to_camera = -w;
    s.importance = film_importance_scale() / (cos_theta * cos_theta * cos_theta);
    return s;
}

// Where a point p is seen on the film; the importance is per unit of area facing the camera at p. Perspective: 1 / d^2
// times the direction's. Orthographic: the image plane's area is the surface's projected area, so the constant part.
FilmSplat project_to_film(vec3 p) {
    vec3 d = p - params.camera_origin.xyz;
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        FilmSplat s = make_invalid_splat();
        vec3 right = params.camera_right.xyz;
        vec3 up = params.camera_up.xyz;
        s.dist = dot(d, params.camera_forward.xyz);  // to the image plane, through the camera's origin
        s.valid = s.dist > 0.0f &&
                  find_film_pixel(dot(d, right) / dot(right, right), dot(d, up) / dot(up, up), s.pixel);
        s.to_camera = -params.camera_forward.xyz;
        s.importance = film_importance_scale();
        return s;
    }
    float dist2 = dot(d, d);
    FilmSplat s = project_direction_to_film(d * inversesqrt(dist2));
    if (!(dist2 > 0.0f)) s.valid = false;
    s.dist = sqrt(dist2);
    s.importance /= dist2;
    return s;
}

// The shadow ray of a splat: from p (error bound p_error, on the side of n the camera is) to the camera; the film
// pixel travels in the item's `path` word.
ShadowRayItem make_splat_ray(vec3 p, vec3 p_error, vec3 n, FilmSplat splat, vec3 contrib, uint origin_triangle) {
    vec3 origin = offset_ray_origin(p, p_error, n, splat.to_camera);
    vec3 target = params.camera_type == CAMERA_ORTHOGRAPHIC ? p + splat.to_camera * splat.dist : params.camera_origin.xyz;
    vec3 d = target - origin;
    float len = length(d);
    ShadowRayItem item;
    item.origin_x = origin.x;
    item.origin_y = origin.y;
    item.origin_z = origin.z;
    item.path = splat.pixel;
    item.dir_x = d.x / len;
    item.dir_y = d.y / len;
    item.dir_z = d.z / len;
    item.t_max = len * (1.0f - 1e-4f);  // pbrt's ShadowEpsilon
    item.contrib_r = contrib.x;
    item.contrib_g = contrib.y;
    item.contrib_b = contrib.z;
    item.origin_triangle = origin_triangle;
    return item;
}

// The shadow ray of a splat of light from infinity seen along w (unit, from the camera): it must escape the scene.
ShadowRayItem make_escape_splat_ray(vec3 w, FilmSplat splat, vec3 contrib) {
    ShadowRayItem item;
    item.origin_x = params.camera_origin.x;
    item.origin_y = params.camera_origin.y;
    item.origin_z = params.camera_origin.z;
    item.path = splat.pixel;
    item.dir_x = w.x;
    item.dir_y = w.y;
    item.dir_z = w.z;
    item.t_max = uintBitsToFloat(0x7f800000u);
    item.contrib_r = contrib.x;
    item.contrib_g = contrib.y;
    item.contrib_b = contrib.z;
    item.origin_triangle = INVALID_INDEX;
    return item;
}

// A splat that adds nothing (its slot in the shadow queue is then skipped by splat.comp).
ShadowRayItem make_empty_splat() {
    ShadowRayItem item;
    item.origin_x = item.origin_y = item.origin_z = 0.0f;
    item.path = 0u;
    item.dir_x = item.dir_y = 0.0f;
    item.dir_z = 1.0f;
    item.t_max = 0.0f;
    item.contrib_r = item.contrib_g = item.contrib_b = 0.0f;
    item.origin_triangle = INVALID_INDEX;
    return item;
}
#endif
