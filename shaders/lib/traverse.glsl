// Closest-hit and any-hit traversal of the linear BVH, shared by the extend and connect stages.
// Robust slab test: no 0 x inf (inverse directions are clamped to +-1e30, which keeps the sign), and the
// far distance is enlarged by 1 + 2 gamma(3) so float rounding never culls a box the ray touches
// (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)). Triangles: watertight test (intersect.glsl).
#ifndef FH_TRAVERSE_GLSL
#define FH_TRAVERSE_GLSL
#include "intersect.glsl"
#include "ray_offset.glsl"

const uint TRAVERSAL_STACK_SIZE = 64u;

struct TraceHit {
    float t;
    uint triangle;  // INVALID_INDEX on a miss
    float b1;
    float b2;
};

vec3 make_safe_inverse(vec3 d) {
    return clamp(vec3(1.0f) / d, vec3(-1e30f), vec3(1e30f));
}

bool intersect_node_bounds(BvhNode node, vec3 origin, vec3 inv_dir, float t_max) {
    vec3 t0 = (vec3(node.min_x, node.min_y, node.min_z) - origin) * inv_dir;
    vec3 t1 = (vec3(node.max_x, node.max_y, node.max_z) - origin) * inv_dir;
    vec3 t_near = min(t0, t1);
    vec3 t_far = max(t0, t1);
    float enter = max(max(t_near.x, t_near.y), max(t_near.z, 0.0f));
    float leave = min(min(t_far.x, t_far.y), min(t_far.z, t_max)) * (1.0f + 2.0f * error_gamma(3.0f));
    return enter <= leave;
}

// any_hit: stop at the first intersection closer than t_max (shadow rays).
TraceHit trace_ray(vec3 origin, vec3 dir, float t_max, bool any_hit) {
    TraceHit best;
    best.t = t_max;
    best.triangle = INVALID_INDEX;
    best.b1 = 0.0f;
    best.b2 = 0.0f;
    RayPrecomp pre = make_ray_precomp(origin, dir);
    vec3 inv_dir = make_safe_inverse(dir);
    uint stack[TRAVERSAL_STACK_SIZE];
    uint stack_size = 0u;
    uint node_index = 0u;
    while (true) {
        BvhNode node = nodes[node_index];
        if (intersect_node_bounds(node, origin, inv_dir, best.t)) {
            uint count = node.count_and_axis & ((1u << BVH_LEAF_COUNT_BITS) - 1u);
            if (count > 0u) {
                for (uint k = 0u; k < count; ++k) {
                    uint tri = node.child_or_first + k;
                    TrianglePositions tp = tri_positions[tri];
                    TriangleHit h = intersect_triangle(pre, vec3(tp.p0_x, tp.p0_y, tp.p0_z),
                                                       vec3(tp.p1_x, tp.p1_y, tp.p1_z),
                                                       vec3(tp.p2_x, tp.p2_y, tp.p2_z), best.t);
                    // Equal distances keep the lower triangle index, whatever the visiting order.
                    if (h.hit != 0u && (h.t < best.t || (h.t == best.t && tri < best.triangle))) {
                        best.t = h.t;
                        best.triangle = tri;
                        best.b1 = h.b1;
                        best.b2 = h.b2;
                        if (any_hit) return best;
                    }
                }
            } else {
                uint axis = node.count_and_axis >> BVH_LEAF_COUNT_BITS;
                // Visit the child on the near side of the split first.
                bool negative = (axis == 0u ? dir.x : (axis == 1u ? dir.y : dir.z)) < 0.0f;
                if (stack_size < TRAVERSAL_STACK_SIZE) {
                    stack[stack_size++] = negative ? node_index + 1u : node.child_or_first;
                }
                node_index = negative ? node.child_or_first : node_index + 1u;
                continue;
            }
        }
        if (stack_size == 0u) break;
        node_index = stack[--stack_size];
    }
    return best;
}
#endif
