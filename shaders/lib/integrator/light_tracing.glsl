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
// Through a thin lens the splat's ray ends at a point drawn uniformly on the aperture, and the same formula holds with
// d and theta measured from there (the lens area's density cancels the importance's 1 / lens area; pbrt-v4's
// PerspectiveCamera::SampleWi); the point lands on the film where the camera ray through that lens point and the
// vertex started. With motion blur the camera stands where it is at the subpath's time. With the Gaussian filter a
// splat adds to every pixel whose filter reaches its film position, weighted by the filter's density there: the
// camera's own samples are drawn from that density (filter importance sampling), so both estimate the same filtered
// pixel. MIS (BDPT) keeps the box filter's density for the camera's strategy: any positive density that every strategy
// uses alike keeps the weights summing to one.
#ifndef FH_LIGHT_TRACING_GLSL
#define FH_LIGHT_TRACING_GLSL
#include "lib/geometry/camera.glsl"
#include "lib/geometry/motion.glsl"
#include "lib/geometry/ray_offset.glsl"

// Where the camera sees a light subpath's vertices from: the camera at the subpath's shutter time, and with a thin
// lens a point on its aperture (the pinhole without one).
struct SplatCamera {
    CameraView view;
    vec3 eye;
};

SplatCamera make_splat_camera(float time, vec2 lens_u) {
    SplatCamera c;
    c.view = camera_view_at(time);
    c.eye = effect_on(EFFECT_THIN_LENS) ? sample_lens_point(c.view, c.view.origin, lens_u) : c.view.origin;
    return c;
}

struct FilmSplat {
    vec3 to_camera;    // unit direction from the point towards the camera
    float dist;        // distance to the camera
    vec3 eye;          // where the splat's ray ends: the eye point (on the lens), or the orthographic image plane
    vec2 film;         // where it lands on the image, in pixels (make_camera_ray's film position)
    uint pixel;        // box filter: the film pixel (row major, a cropped film's own)
    float importance;  // what a unit of radiance sent towards the camera adds to the film (box: to that pixel's sum)
    bool valid;        // false: behind the camera, or where no film pixel's filter reaches
};

// A film position (pixels) from normalised device coordinates (make_camera_ray's).
vec2 film_position_of_ndc(float ndc_x, float ndc_y) {
    return vec2((ndc_x + 1.0f) * 0.5f * float(params.width), (1.0f - ndc_y) * 0.5f * float(params.height));
}

// The film pixel a film position falls in, if it is on the film (inside the crop).
bool find_film_pixel(vec2 film, out uint pixel) {
    pixel = 0u;
    float fx = film.x, fy = film.y;
    if (!(fx >= 0.0f && fx < float(params.width) && fy >= 0.0f && fy < float(params.height))) return false;
    uint x = min(uint(fx), params.width - 1u), y = min(uint(fy), params.height - 1u);
    if (x < params.crop_x || y < params.crop_y) return false;
    x -= params.crop_x;
    y -= params.crop_y;
    if (x >= params.film_width || y >= params.film_height) return false;
    pixel = y * params.film_width + x;
    return true;
}

// True where a splat at this film position adds to some film pixel: the pixel it falls in (box filter), or any whose
// Gaussian reaches it (a camera sample of an edge pixel may leave the image by up to the radius).
bool film_position_counts(vec2 film, out uint pixel) {
    if (params.filter_type != FILTER_GAUSSIAN) return find_film_pixel(film, pixel);
    pixel = 0u;
    float r = params.filter_radius;
    vec2 lo = vec2(params.crop_x, params.crop_y) + vec2(0.5f - r);
    vec2 hi = vec2(params.crop_x + params.film_width, params.crop_y + params.film_height) - vec2(0.5f - r);
    return all(greaterThanEqual(film, lo)) && all(lessThanEqual(film, hi));
}

// Splats that land by film position (motion blur: the camera moves; the Gaussian filter: several pixels) carry their
// light subpath's index, from which splat.comp finds the time and projects the ray again; the others their pixel.
// A specialisation constant (the host sets it for either), so the box filter's splats compile none of it.
layout(constant_id = SPEC_SPLATS_BY_PATH) const bool splats_by_path_on = false;
bool splats_by_path() { return splats_by_path_on; }

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
    s.eye = vec3(0.0f);
    s.film = vec2(0.0f);
    s.pixel = 0u;
    s.importance = 0.0f;
    s.valid = false;
    return s;
}

// The film position of the perspective camera ray that leaves the eye point along w (unit, cos_theta = w . forward
// > 0): through a lens, the pinhole ray that meets w's ray on the plane in focus.
vec2 film_position_along(SplatCamera cam, vec3 w, float cos_theta) {
    vec3 on_plane = w / cos_theta;  // on the image plane at unit distance along forward
    if (effect_on(EFFECT_THIN_LENS)) {
        vec3 d = cam.eye + (params.focus_distance / cos_theta) * w - cam.view.origin;
        on_plane = d / dot(d, cam.view.forward);
    }
    vec3 right = cam.view.right;
    vec3 up = cam.view.up;
    return film_position_of_ndc(dot(on_plane, right) / dot(right, right), dot(on_plane, up) / dot(up, up));
}

// The film position of an orthographic camera ray through (or from) the point p.
vec2 film_position_orthographic(CameraView view, vec3 p) {
    vec3 d = p - view.origin;
    return film_position_of_ndc(dot(d, view.right) / dot(view.right, view.right),
                                dot(d, view.up) / dot(view.up, view.up));
}

// Where direction w (unit, from the eye) is seen on the film of the perspective camera (the inverse of
// make_camera_ray); the importance is per unit of solid angle there (a light at infinity). An orthographic camera sees
// one direction only: never a sampled one.
FilmSplat project_direction_to_film(SplatCamera cam, vec3 w) {
    FilmSplat s = make_invalid_splat();
    float cos_theta = dot(w, cam.view.forward);
    if (params.camera_type == CAMERA_ORTHOGRAPHIC || !(cos_theta > 0.0f)) return s;
    s.film = film_position_along(cam, w, cos_theta);
    s.valid = film_position_counts(s.film, s.pixel);
    s.to_camera = -w;
    s.eye = cam.eye;
    s.importance = film_importance_scale() / (cos_theta * cos_theta * cos_theta);
    return s;
}

// Where a point p is seen on the film; the importance is per unit of area facing the camera at p. Perspective: 1 / d^2
// times the direction's, d from the eye. Orthographic: the image plane's area is the surface's projected area, so the
// constant part.
FilmSplat project_to_film(SplatCamera cam, vec3 p) {
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        FilmSplat s = make_invalid_splat();
        s.dist = dot(p - cam.view.origin, cam.view.forward);  // to the image plane, through the camera's origin
        s.film = film_position_orthographic(cam.view, p);
        s.valid = s.dist > 0.0f && film_position_counts(s.film, s.pixel);
        s.to_camera = -cam.view.forward;
        s.eye = p + s.to_camera * s.dist;
        s.importance = film_importance_scale();
        return s;
    }
    vec3 d = p - cam.eye;
    float dist2 = dot(d, d);
    FilmSplat s = project_direction_to_film(cam, d * inversesqrt(dist2));
    if (!(dist2 > 0.0f)) s.valid = false;
    s.dist = sqrt(dist2);
    s.importance /= dist2;
    return s;
}

// The film position of a splat's ray again (splats_by_path; splat.comp): the ray ends at the eye, or for light from
// infinity leaves the scene from it. False where it is behind the camera.
bool find_splat_film_position(ShadowRayItem item, out vec2 film) {
    film = vec2(0.0f);
    SplatCamera cam;
    cam.view = camera_view_at(load_path_time(item.path));
    vec3 origin = vec3(item.origin_x, item.origin_y, item.origin_z);
    vec3 dir = vec3(item.dir_x, item.dir_y, item.dir_z);
    bool from_infinity = isinf(item.t_max);
    cam.eye = from_infinity ? origin : origin + dir * (item.t_max / (1.0f - 1e-4f));
    if (params.camera_type == CAMERA_ORTHOGRAPHIC) {
        film = film_position_orthographic(cam.view, cam.eye);
        return true;
    }
    vec3 w = from_infinity ? dir : -dir;  // from the eye
    float cos_theta = dot(w, cam.view.forward);
    if (!(cos_theta > 0.0f)) return false;
    film = film_position_along(cam, w, cos_theta);
    return true;
}

// The shadow ray of a splat: from p (error bound p_error, on the side of n the camera is) to the eye; the item's
// `path` word holds the film pixel, or the light subpath's index (splats_by_path).
ShadowRayItem make_splat_ray(vec3 p, vec3 p_error, vec3 n, FilmSplat splat, vec3 contrib, uint origin_triangle,
                             uint subpath) {
    vec3 origin = offset_ray_origin(p, p_error, n, splat.to_camera);
    vec3 d = splat.eye - origin;
    float len = length(d);
    ShadowRayItem item;
    item.origin_x = origin.x;
    item.origin_y = origin.y;
    item.origin_z = origin.z;
    item.path = splats_by_path() ? subpath : splat.pixel;
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

// The shadow ray of a splat of light from infinity seen along w (unit, from the eye): it must escape the scene.
ShadowRayItem make_escape_splat_ray(vec3 w, FilmSplat splat, vec3 contrib, uint subpath) {
    ShadowRayItem item;
    item.origin_x = splat.eye.x;
    item.origin_y = splat.eye.y;
    item.origin_z = splat.eye.z;
    item.path = splats_by_path() ? subpath : splat.pixel;
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
