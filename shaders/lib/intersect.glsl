// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection",
// JCGT 2(1)), in the GLSL/C++ shared subset of cpp_compat.h.
//
// The ray is sheared so that it runs along +z through the origin; the triangle is projected with the same
// per-vertex arithmetic, so triangles sharing an edge compute bit-identical (negated) edge functions and no
// ray slips between them. `precise` keeps the GPU compiler from fusing the edge-function products into
// FMAs, which would break that symmetry (x86-64 C++ without -mfma never contracts).
#ifndef FREDHOLM_LIB_INTERSECT_GLSL
#define FREDHOLM_LIB_INTERSECT_GLSL

#ifdef __cplusplus
#define FH_PRECISE
#else
#define FH_PRECISE precise
#endif

// Per-ray constants (paper sec. 3.1): kz is the dominant axis of the direction, kx and ky the others
// (swapped when dir[kz] < 0 to keep the winding), and the shear that maps the direction to +z.
struct RayPrecomp {
    vec3 origin;
    uint kx, ky, kz;
    float sx, sy, sz;
};

// hit != 0 when the ray meets the triangle at t in (0, t_max); b1, b2 weight p1 and p2 (p0 gets 1 - b1 - b2).
struct TriangleHit {
    float t;
    float b1;
    float b2;
    uint hit;
};

RayPrecomp make_ray_precomp(vec3 origin, vec3 dir) {
    vec3 a = abs(dir);
    uint kz = 2u;
    if (a.x >= a.y && a.x >= a.z) {
        kz = 0u;
    } else if (a.y >= a.z) {
        kz = 1u;
    }
    uint kx = kz == 2u ? 0u : kz + 1u;
    uint ky = kx == 2u ? 0u : kx + 1u;
    if (dir[kz] < 0.0f) {
        uint swap_tmp = kx;
        kx = ky;
        ky = swap_tmp;
    }
    RayPrecomp r;
    r.origin = origin;
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.sx = dir[kx] / dir[kz];
    r.sy = dir[ky] / dir[kz];
    r.sz = 1.0f / dir[kz];
    return r;
}

// Backfaces count (no culling).
TriangleHit intersect_triangle(RayPrecomp r, vec3 p0, vec3 p1, vec3 p2, float t_max) {
    TriangleHit miss;
    miss.t = t_max;
    miss.b1 = 0.0f;
    miss.b2 = 0.0f;
    miss.hit = 0u;

    // Vertices relative to the origin, then sheared and scaled (paper eq. 4).
    vec3 a = p0 - r.origin;
    vec3 b = p1 - r.origin;
    vec3 c = p2 - r.origin;
    FH_PRECISE float ax = a[r.kx] - r.sx * a[r.kz];
    FH_PRECISE float ay = a[r.ky] - r.sy * a[r.kz];
    FH_PRECISE float bx = b[r.kx] - r.sx * b[r.kz];
    FH_PRECISE float by = b[r.ky] - r.sy * b[r.kz];
    FH_PRECISE float cx = c[r.kx] - r.sx * c[r.kz];
    FH_PRECISE float cy = c[r.ky] - r.sy * c[r.kz];

    // Scaled barycentrics: 2D edge functions of the projected triangle (u weights p0, v p1, w p2).
    FH_PRECISE float u = cx * by - cy * bx;
    FH_PRECISE float v = ax * cy - ay * cx;
    FH_PRECISE float w = bx * ay - by * ax;
    // A ray exactly on an edge gives 0 there; mixed signs mean the ray passes outside.
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) {
        return miss;
    }
    float det = u + v + w;
    if (det == 0.0f) {
        return miss;  // the ray lies in the triangle's plane, or the triangle has no area
    }

    // Scaled distance (paper sec. 3.3). The range test is done on t itself, not on t_scaled against
    // t_max * det as in the paper: the two can round differently, and a hit must never come back with
    // t == t_max, or a closest-hit search would depend on the order it visits triangles in.
    float az = r.sz * a[r.kz];
    float bz = r.sz * b[r.kz];
    float cz = r.sz * c[r.kz];
    float t_scaled = u * az + v * bz + w * cz;
    float inv_det = 1.0f / det;
    float t = t_scaled * inv_det;
    if (!(t > 0.0f && t < t_max)) {
        return miss;
    }

    TriangleHit h;
    h.t = t;
    h.b1 = v * inv_det;
    h.b2 = w * inv_det;
    h.hit = 1u;
    return h;
}

// Ray/box slab test that never culls a triangle intersect_triangle would report. The triangle test is
// conservative, not exact: it tests the sheared ray, which may pass a few ulps beside the real one, so
// "we must dynamically enlarge bounds during BVH traversal" (Woop et al. 2013, sec. 5). The box grows by
// 2^-20 of the largest origin-to-box distance (the shear's error is ~8 ulp of it), and the far distance
// by 1 + 2 gamma(3) for the slab arithmetic (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)).
// inv_dir: 1 / dir with each component clamped to +-1e30, so a zero component never makes 0 * inf.
// Returns (enter, leave): the box is hit when enter <= leave; enter orders the children of a node.
vec2 box_entry_exit(vec3 origin, vec3 inv_dir, vec3 lo, vec3 hi, float t_max) {
    vec3 reach = max(abs(lo - origin), abs(hi - origin));
    float pad = max(max(reach.x, reach.y), reach.z) * 9.5367431640625e-7f;  // 2^-20
    vec3 t0 = (lo - vec3(pad) - origin) * inv_dir;
    vec3 t1 = (hi + vec3(pad) - origin) * inv_dir;
    vec3 t_near = min(t0, t1);
    vec3 t_far = max(t0, t1);
    float enter = max(max(t_near.x, t_near.y), max(t_near.z, 0.0f));
    float leave = min(min(t_far.x, t_far.y), min(t_far.z, t_max)) * 1.0000004768371582f;  // 1 + 2^-21 >= 1 + 2 gamma(3)
    vec2 range;
    range.x = enter;
    range.y = leave;
    return range;
}

uint intersect_box(vec3 origin, vec3 inv_dir, vec3 lo, vec3 hi, float t_max) {
    vec2 range = box_entry_exit(origin, inv_dir, lo, hi, t_max);
    return range.x <= range.y ? 1u : 0u;
}

// 1 / dir, clamped so that intersect_box needs no special case for zero components.
vec3 make_safe_inverse_dir(vec3 dir) {
    return clamp(vec3(1.0f) / dir, vec3(-1e30f), vec3(1e30f));
}

#undef FH_PRECISE
#endif
