// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection",
// JCGT 2(1)), in the GLSL/C++ shared subset of cpp_compat.h.
//
// The ray is sheared so that it runs along +z through the origin; the triangle is projected with the same
// per-vertex arithmetic, so triangles sharing an edge compute bit-identical (negated) edge functions and no
// ray slips between them. `precise` keeps the GPU compiler from fusing the edge-function products into
// FMAs, which would break that symmetry (x86-64 C++ without -mfma never contracts).
#ifndef FH_INTERSECT_GLSL
#define FH_INTERSECT_GLSL
#include "lib/core/techniques.glsl"

#ifdef __cplusplus
#define FH_PRECISE
#else
#define FH_PRECISE precise
#endif

// Per-ray constants (paper sec. 3.1): kz is the dominant axis of the direction, kx and ky the others
// (swapped when dir[kz] < 0 to keep the winding), and the shear that maps the direction to +z.
struct RayPrecomp {
    vec3 origin;
    vec3 dir;
    uint kx, ky, kz;
    float sx, sy, sz;
};

// hit != 0 when the ray meets the triangle at t in (0, t_max); b1, b2 weight p1 and p2 (p0 gets 1 - b1 - b2).
// hit == HIT_UNCERTAIN: t is positive but within its own rounding error of 0, so the ray may really start on
// the far side of the triangle's plane (traverse.glsl rejects such a hit on the surface the ray leaves).
const uint HIT_CERTAIN = 1u;
const uint HIT_UNCERTAIN = 2u;

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
    r.dir = dir;
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.sx = dir[kx] / dir[kz];
    r.sy = dir[ky] / dir[kz];
    r.sz = 1.0f / dir[kz];
    return r;
}

// The classic test (Moller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection"), used only
// when TECHNIQUE_WATERTIGHT is switched off: its edge tests are not consistent between neighbouring
// triangles, so rays through shared edges and vertices can slip through a closed mesh.
TriangleHit intersect_triangle_unsafe(RayPrecomp r, vec3 p0, vec3 p1, vec3 p2, float t_max) {
    TriangleHit h;
    h.t = t_max;
    h.b1 = 0.0f;
    h.b2 = 0.0f;
    h.hit = 0u;
    vec3 e1 = p1 - p0;
    vec3 e2 = p2 - p0;
    vec3 pv = cross(r.dir, e2);
    float det = dot(e1, pv);
    if (det == 0.0f) return h;
    float inv_det = 1.0f / det;
    vec3 tv = r.origin - p0;
    float b1 = dot(tv, pv) * inv_det;
    vec3 qv = cross(tv, e1);
    float b2 = dot(r.dir, qv) * inv_det;
    float t = dot(e2, qv) * inv_det;
    if (b1 < 0.0f || b2 < 0.0f || b1 + b2 > 1.0f || !(t > 0.0f && t < t_max)) return h;
    h.t = t;
    h.b1 = b1;
    h.b2 = b2;
    h.hit = 1u;
    return h;
}

// max(|a|, |b|, |c|) as an integer max of the magnitudes' bits, which order as the floats do (a float max of two
// variables is three instructions on lavapipe, for NaN, which a lane whose hit counts never has here).
float max_magnitude(float a, float b, float c) {
    return uintBitsToFloat(max(max(floatBitsToUint(abs(a)), floatBitsToUint(abs(b))), floatBitsToUint(abs(c))));
}

// Backfaces count (no culling).
TriangleHit intersect_triangle(RayPrecomp r, vec3 p0, vec3 p1, vec3 p2, float t_max) {
    if (!FH_TECHNIQUE_ON(TECHNIQUE_WATERTIGHT)) return intersect_triangle_unsafe(r, p0, p1, p2, t_max);
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
    if (!(t < t_max)) {
        return miss;
    }
    // Is t farther from 0 than its own rounding error? If not, the ray may start on either side of the
    // triangle's plane: a ray leaving a large triangle could re-hit it at a spurious positive t (the error of
    // t grows with the triangle's size, the origin offset of ray_offset.glsl only with |p|), and a ray leaving
    // a wall near a corner may start a rounding error behind the adjacent wall. The bound is pbrt-v4's
    // (Triangle::Intersect, Pharr et al. 2023, sec. 6.8.7; gamma(n) = n u / (1 - n u)). pbrt rejects every
    // t <= bound, which lets rays out of closed rooms through their corners; here such a hit is reported as
    // HIT_UNCERTAIN at t >= 0 and traverse.glsl rejects it only on the surface the ray leaves.
    float max_xt = max_magnitude(ax, bx, cx);
    float max_yt = max_magnitude(ay, by, cy);
    float max_zt = max_magnitude(az, bz, cz);
    const float gamma2 = 1.1920930376163766e-7f, gamma3 = 1.788139663006007e-7f, gamma5 = 2.9802331269482156e-7f;
    float delta_z = gamma3 * max_zt;
    float delta_x = gamma5 * (max_xt + max_zt);
    float delta_y = gamma5 * (max_yt + max_zt);
    float delta_e = 2.0f * (gamma2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    float max_e = max_magnitude(u, v, w);
    float delta_t = 3.0f * (gamma3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * abs(inv_det);
    if (!(t > -delta_t)) {
        return miss;
    }
    uint certainty = t <= delta_t ? HIT_UNCERTAIN : HIT_CERTAIN;

    TriangleHit h;
    h.t = max(t, 0.0f);
    h.b1 = v * inv_det;
    h.b2 = w * inv_det;
    h.hit = certainty;
    return h;
}

// The slab tests of a wide node's children (traverse.glsl), which never cull a triangle intersect_triangle would report.
// The triangle test is conservative, not exact: it tests the sheared ray, which may pass a few ulps beside the real
// one, so "we must dynamically enlarge bounds during BVH traversal" (Woop et al. 2013, sec. 5). Every box grows by
// `pad` (box_padding), and the far distance by 1 + 2 gamma(3) for the slab arithmetic (Ize 2013, "Robust BVH Ray
// Traversal", JCGT 2(2)).
//
// A child's box planes lie at node_origin + q step, q a byte and step a power of two (layout.h BvhWideNode), and the
// host quantises so that the exact value of that sum is outside the child's triangles (wide_bvh.cpp). So the distance
// to the plane q along an axis is q (step / dir) + (node_origin - origin) / dir: the node's frame (make_node_frame)
// takes the second term and the scale once per node, and each plane is then one fma (Ylitie et al. 2017, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", sec. 3.2), where forming the plane and then its
// distance took five operations. The roundings this adds (the difference, the products, the fma: at most about 6
// ulps of the reach) and those of the triangle test (about 8) stay inside the padding of 32 (box_padding).
//
// Which plane of a slab a ray crosses first follows from its direction's sign, so the frame picks the sides once per
// node (the low planes along an axis the ray travels up, the high ones along an axis it travels down) and a child
// needs no min and max to order its two distances per axis: on lavapipe each min or max of two variables is three
// instructions (NaN handling), a pick of a node's packed plane words one, for all four children. The picked
// distances are the ones min and max would return (padded low planes never lie beyond padded high ones), so the same
// children are hit.
struct NodeFrame {
    vec3 scale;        // step * inv_dir
    vec3 near_offset;  // (node_origin -+ pad - origin) * inv_dir: where the plane q = 0 of the side entered is crossed
    vec3 far_offset;   // (node_origin +- pad - origin) * inv_dir: the same for the side left
    bvec3 down;        // the ray travels down the axis (inv_dir < 0): it enters through the high planes
};

NodeFrame make_node_frame(vec3 node_origin, vec3 step, vec3 origin, vec3 inv_dir, float pad) {
    vec3 to_node = node_origin - origin;
    NodeFrame f;
    f.down = lessThan(inv_dir, vec3(0.0f));
    vec3 near_pad = mix(vec3(pad), vec3(-pad), f.down);
    f.scale = step * inv_dir;
    f.near_offset = (to_node - near_pad) * inv_dir;
    f.far_offset = (to_node + near_pad) * inv_dir;
    return f;
}

// Of a node's (or a child's) low and high plane words, those of the side entered and of the side left per axis.
uvec3 near_planes(NodeFrame f, uvec3 lo_q, uvec3 hi_q) { return mix(lo_q, hi_q, f.down); }
uvec3 far_planes(NodeFrame f, uvec3 lo_q, uvec3 hi_q) { return mix(hi_q, lo_q, f.down); }

// (enter, leave) of the child whose box spans the planes near_q (the side entered, near_planes) to far_q steps of the
// node frame `f` (the steps as floats, exact below 256); the box is hit when enter <= leave, and enter orders the
// children of a node.
vec2 child_entry_exit(NodeFrame f, vec3 near_q, vec3 far_q, float t_max) {
    bool conservative = FH_TECHNIQUE_ON(TECHNIQUE_CONSERVATIVE_BOX);
    vec3 t_near = fma(near_q, f.scale, f.near_offset);
    vec3 t_far = fma(far_q, f.scale, f.far_offset);
    // max(0, t_near) and min(t_far, t_max) as integer max and min of the floats' bits (one instruction each on
    // lavapipe, where a float min or max of two variables is three: it handles NaN, which the frame never makes).
    // Signed integers order non-negative floats as floats do, so `enter` is exact; `leave` is exact when no far
    // distance is negative, and negative (a miss, as before) when one is: a negative float is a negative integer.
    int enter_bits = max(max(floatBitsToInt(max(t_near.x, 0.0f)), floatBitsToInt(max(t_near.y, 0.0f))),
                         floatBitsToInt(max(t_near.z, 0.0f)));
    int leave_bits = min(min(floatBitsToInt(t_far.x), floatBitsToInt(t_far.y)),
                         min(floatBitsToInt(t_far.z), floatBitsToInt(t_max)));
    float enter = intBitsToFloat(enter_bits);
    float leave = intBitsToFloat(leave_bits) * (conservative ? 1.0000004768371582f : 1.0f);  // 1 + 2^-21 >= 1 + 2 gamma(3)
    vec2 range;
    range.x = enter;
    range.y = leave;
    return range;
}

// The padding the node frames need for every box inside [lo, hi] (the whole scene's: traversal computes it once per
// ray from the scene's bounds): 2^-19 of the largest distance from the origin to that box along an axis (the reach);
// 0 without TECHNIQUE_CONSERVATIVE_BOX.
float box_padding(vec3 origin, vec3 lo, vec3 hi) {
    if (!FH_TECHNIQUE_ON(TECHNIQUE_CONSERVATIVE_BOX)) return 0.0f;
    vec3 reach = max(abs(lo - origin), abs(hi - origin));
    return max(max(reach.x, reach.y), reach.z) * 1.9073486328125e-6f;  // 2^-19
}

// 1 / dir, each component clamped to +-min(1e30, 2^104 / pad), that is 2^123 / reach (box_padding: reach = 2^19 pad):
// the node frame's terms stay finite (no 0 x inf, and no inf - inf between its two terms), as each is at most about
// 10 reaches (node extents and distances inside the scene, through an instance's map too) times the clamp, below
// 2^127. A clamped component tilts the ray by at most 1 / clamp, which moves it less than 8 ulps of the reach while
// it is inside the scene, as long as the reach is below 1.4e30: every coordinate the GPU sees stays within
// MAX_RENDER_COORDINATE (layout.h), which keeps the reach below 2.1e29. pad: box_padding's, for the ray's space.
// Without TECHNIQUE_CONSERVATIVE_BOX it is the plain 1 / dir: an axis-parallel ray then computes 0 x inf = NaN, and
// min/max drop or keep the box depending on argument order.
vec3 make_safe_inverse_dir(vec3 dir, float pad) {
    if (!FH_TECHNIQUE_ON(TECHNIQUE_CONSERVATIVE_BOX)) return vec3(1.0f) / dir;
    float limit = min(1e30f, 2.028240960365167e31f / pad);  // 2^104 / pad; 1e30 for pad 0
    return clamp(vec3(1.0f) / dir, vec3(-limit), vec3(limit));
}

#undef FH_PRECISE
#endif
