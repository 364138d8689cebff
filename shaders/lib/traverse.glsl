// Closest-hit and any-hit traversal of the linear BVH, shared by the extend and connect stages.
// Box and triangle tests come from intersect.glsl: a slab test without 0 x inf, padded as the watertight
// triangle test requires (Woop et al. 2013, sec. 5) and with the far distance enlarged by 1 + 2 gamma(3)
// (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)).
#ifndef FH_TRAVERSE_GLSL
#define FH_TRAVERSE_GLSL
#include "intersect.glsl"

const uint TRAVERSAL_STACK_SIZE = 64u;

struct TraceHit {
    float t;
    uint triangle;  // INVALID_INDEX on a miss
    float b1;
    float b2;
};

// any_hit: stop at the first intersection closer than t_max (shadow rays).
TraceHit trace_ray(vec3 origin, vec3 dir, float t_max, bool any_hit) {
    TraceHit best;
    best.t = t_max;
    best.triangle = INVALID_INDEX;
    best.b1 = 0.0f;
    best.b2 = 0.0f;
    RayPrecomp pre = make_ray_precomp(origin, dir);
    vec3 inv_dir = make_safe_inverse_dir(dir);
    uint stack[TRAVERSAL_STACK_SIZE];
    uint stack_size = 0u;
    uint node_index = 0u;
    while (true) {
        BvhNode node = uniform_nodes[node_index];
        if (intersect_box(origin, inv_dir, vec3(node.min_x, node.min_y, node.min_z),
                          vec3(node.max_x, node.max_y, node.max_z), best.t) != 0u) {
            uint count = node.count_and_axis & ((1u << BVH_LEAF_COUNT_BITS) - 1u);
            if (count > 0u) {
                for (uint k = 0u; k < count; ++k) {
                    uint tri = node.child_or_first + k;
                    TrianglePositions tp = uniform_tri_positions[tri];
                    TriangleHit h = intersect_triangle(pre, vec3(tp.p0_x, tp.p0_y, tp.p0_z),
                                                       vec3(tp.p1_x, tp.p1_y, tp.p1_z),
                                                       vec3(tp.p2_x, tp.p2_y, tp.p2_z), best.t);
                    if (h.hit != 0u) {  // intersect_triangle only reports t < best.t
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
