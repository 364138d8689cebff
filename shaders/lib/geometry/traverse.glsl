// Closest-hit and any-hit traversal of the 4-wide BVH (layout.h BvhWideNode), shared by the extend and connect stages.
// Box and triangle tests come from intersect.glsl: a slab test without 0 x inf, padded as the watertight
// triangle test requires (Woop et al. 2013, sec. 5) and with the far distance enlarged by 1 + 2 gamma(3)
// (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)).
#ifndef FH_TRAVERSE_GLSL
#define FH_TRAVERSE_GLSL
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require
#include "lib/geometry/intersect.glsl"
#include "lib/geometry/ray_offset.glsl"
#include "lib/material/material.glsl"
#include "lib/geometry/instance.glsl"
#include "lib/geometry/motion.glsl"

struct TraceHit {
    float t;
    uint triangle;  // INVALID_INDEX on a miss
    float b1;
    float b2;
    uint instance;  // the Instance the triangle was hit in (scene_has_instances), else INVALID_INDEX
};

// any_hit: stop at the first intersection closer than t_max (shadow rays). origin_triangle: the triangle the
// ray leaves (INVALID_INDEX for camera rays). A hit whose t lies within its own rounding error of 0
// (intersect.glsl HIT_UNCERTAIN) is rejected on that triangle and on any triangle parallel to it (its
// coplanar neighbours: the same surface), and kept on any other (the adjacent wall of a corner).
//
// Closest hit is deterministic whatever the BVH: hits at exactly the same t (coplanar overlapping triangles,
// a ray through a shared edge) go to the triangle that comes first in the scene (TrianglePositions.
// source_index), not to the one visited first. Triangles are tested up to the next float above the best t
// so that ties come back; the index is loaded only for a tie.
//
// Two-level BVH (scene_has_instances): a top-level leaf (kind WIDE_INSTANCE_COUNT) names an Instance; the ray is
// mapped to the mesh's object space (an affine map keeps t: the object-space ray is parametrised like the
// world one) and traversal goes on at the mesh BVH's root on the same stack. Entries pushed from then on sit at
// or above `instance_base`; popping one below it returns to the top level with the world-space ray.
//
// "While-while" traversal (Aila & Laine 2009): the inner loop descends through wide nodes until this lane
// holds a leaf, then the lanes test their leaves' triangles together. On lavapipe every branch of an `if`
// runs (masked) for the whole SIMD group, so keeping triangle tests out of the node loop means a node step
// never pays for a triangle test, and each leaf loop tests the triangles of all lanes at once.
//
// A lane does not leave the node loop, nor the loop around it, on its own: one that holds its leaf, or has finished,
// goes on idle (its state kept by selects) until the whole SIMD group leaves (subgroupAll). On lavapipe an idle lane
// costs what a masked one does, but a store to the stack (a scatter over the 8 lanes) under a mask that varies from
// step to step branches on each lane's bit, and those branches mispredict: with the lanes kept in, the Cornell box's
// rays traced 10% faster (tests/bench/RESULTS.md "Speed").
//
// On lavapipe both sides of every branch run (masked) for the whole SIMD group, so nothing rare may load inside the
// triangle loop: the origin triangle's normal is loaded once per ray, and the best hit's source index is kept.
//
// Alpha (EFFECT_ALPHA): whether a candidate hit on a cut-out or blended triangle counts needs its material and
// texture. Asked inside the triangle loop, that code ran (masked) at every triangle test of every ray, and made the
// extend stage 2.5x slower on FlightHelmet, where one material of six blends. So a candidate on a triangle flagged
// TRIANGLE_ALPHA_TESTED suspends traversal: the loops are left with the candidate and the leaf's remaining
// triangles kept, the coverage is asked outside them, and traversal resumes where it stopped. Candidates are taken
// or refused in the same order as before, so the hits (and the images) keep their bits.
// The triangle's normal, not normalised (its length is twice the area).
vec3 triangle_normal(TrianglePositions tp) {
    return cross(vec3(tp.p1_x, tp.p1_y, tp.p1_z) - vec3(tp.p0_x, tp.p0_y, tp.p0_z),
                 vec3(tp.p2_x, tp.p2_y, tp.p2_z) - vec3(tp.p0_x, tp.p0_y, tp.p0_z));
}

// origin_normal: the origin triangle's unit normal (unused without one). The cosine is compared against the length of
// the other triangle's normal rather than normalising it: on lavapipe `normalize` is a square root and three divisions,
// which ran (masked) at every triangle test.
bool is_same_surface(uint tri, TrianglePositions tp, uint origin_triangle, vec3 origin_normal) {
    if (origin_triangle == INVALID_INDEX) return false;
    if (tri == origin_triangle) return true;
    vec3 n = triangle_normal(tp);
    return abs(dot(n, origin_normal)) > 0.99999f * length(n);  // parallel within ~0.26 degrees
}

// A child of a wide node as traversal sorts it: where its box is entered (MISSED_CHILD: not hit), and what it is.
const float MISSED_CHILD = 3.0e38f;  // above any entry distance a hit box has (at most best.t, finite)
struct ChildEntry {
    float entry;
    uint word;  // index << WIDE_COUNT_BITS | kind (0: a node; WIDE_INSTANCE_COUNT: an instance; else triangles)
};

// The word of the slot whose kind is in the low bits of `kinds` (INVALID_INDEX for none), which it shifts out.
// Indices are implicit (layout.h BvhWideNode): interior children take consecutive nodes, leaves consecutive
// triangles (an instance one), in slot order.
uint take_child_word(inout uint kinds, inout uint next_node, inout uint next_leaf) {
    uint kind = kinds & ((1u << WIDE_COUNT_BITS) - 1u);
    kinds >>= WIDE_COUNT_BITS;
    uint word = kind == 0u ? next_node << WIDE_COUNT_BITS : (next_leaf << WIDE_COUNT_BITS | kind);
    next_node += kind == 0u ? 1u : 0u;
    next_leaf += kind == WIDE_INSTANCE_COUNT ? 1u : (kind < WIDE_INSTANCE_COUNT ? kind : 0u);
    return kind == WIDE_NO_CHILD ? INVALID_INDEX : word;
}

// float(q) for q < 2^23 as an OR and a subtraction (2^23 + q has q in its mantissa), exact like the conversion it
// replaces: on lavapipe the extend stage ran about 5% faster with it (tests/bench/RESULTS.md "Speed").
vec3 byte_to_float(uvec3 q) {
    return uintBitsToFloat(q | 0x4b000000u) - 8388608.0f;
}

// Child slot `shift / 8` of a wide node, tested in the node's frame (intersect.glsl make_node_frame).
// near_q, far_q: the node's plane words of the sides entered and left (intersect.glsl near_planes).
ChildEntry test_child(uint child, uint shift, NodeFrame frame, uvec3 near_q, uvec3 far_q, float t_max) {
    vec2 range = child_entry_exit(frame, byte_to_float(near_q >> shift & 0xffu), byte_to_float(far_q >> shift & 0xffu),
                                  t_max);
    ChildEntry e;
    e.entry = range.x <= range.y && child != INVALID_INDEX ? range.x : MISSED_CHILD;
    e.word = child;
    return e;
}

void order_entries(inout ChildEntry a, inout ChildEntry b) {
    bool swap = b.entry < a.entry;
    ChildEntry first = swap ? b : a;
    b = swap ? a : b;
    a = first;
}

uint child_index(uint word) { return word >> WIDE_COUNT_BITS; }
uint child_count(uint word) { return word & ((1u << WIDE_COUNT_BITS) - 1u); }

// A macro, not a function: GLSL passes arrays by copy, and the stack is trace_ray's. The host keeps every tree within
// the stack (scene_bvh.cpp check_stack_bound); the bound check only keeps a write in range. An entry is the child's
// word: one word where index and count took two (on lavapipe the stack lives in scratch memory, one scattered store
// per word and lane; tests/bench/RESULTS.md "Wide BVH nodes" has the A/B rounds). The word is stored whether or not the child was
// hit, above the top where it was not (the array's last entry takes a store at a full stack), and only the size
// depends on the hit: on lavapipe a store under a per-lane condition cost more than the store itself.
#define PUSH_WORD(word, wanted)                                                             \
    stack[min(stack_size, TRAVERSAL_STACK_SIZE + 1u)] = (word);                              \
    stack_size += (wanted) && stack_size < TRAVERSAL_STACK_SIZE + 1u ? 1u : 0u;
// live: the lane is descending (an idle lane's store lands above its top and does not count).
#define PUSH_ENTRY(e, live) PUSH_WORD((e).word, (live) && (e).entry < MISSED_CHILD)

// Takes the top stack entry; one pushed at the top level (below instance_base) returns the ray to world space.
// [[dont_flatten]]: as selects (glslang's choice) the copies of the ray stayed in a one-level scene's loops after
// specialisation, 120 of the node loop's 800 instructions on lavapipe (test_spirv_specialise, tests/bench/RESULTS.md "Speed").
#define LEAVE_INSTANCE_BELOW_BASE()                                                            \
    [[dont_flatten]] if (scene_has_instances && instance != INVALID_INDEX && stack_size < instance_base) { \
        instance = INVALID_INDEX;                                                              \
        origin = world_origin;                                                                 \
        dir = world_dir;                                                                       \
        pre = make_ray_precomp(origin, dir);                                                   \
        pad = world_pad;                                                                       \
        inv_dir = make_safe_inverse_dir(dir, pad);                                             \
    }

#define POP_ENTRY()                                                                            \
    --stack_size;                                                                              \
    index = child_index(stack[stack_size]);                                                    \
    count = child_count(stack[stack_size]);                                                    \
    LEAVE_INSTANCE_BELOW_BASE()

// alpha_seed: with EFFECT_ALPHA, the ray's key for stochastic alpha (material.glsl is_surface_present); a
// candidate hit on a cut-out or not-drawn-this-time point is skipped as if the triangle were not there.
// time: the ray's time in the shutter (motion.glsl; read only with EFFECT_MOTION_BLUR).
TraceHit trace_ray(vec3 origin, vec3 dir, float t_max, bool any_hit, uint origin_triangle, uint alpha_seed,
                   float time) {
    TraceHit best;
    best.t = t_max;
    best.triangle = INVALID_INDEX;
    best.b1 = 0.0f;
    best.b2 = 0.0f;
    best.instance = INVALID_INDEX;
    vec3 world_origin = origin;
    vec3 world_dir = dir;
    uint instance = INVALID_INDEX;  // the instance whose mesh BVH this lane is in
    uint instance_base = 0u;        // stack size when it was entered
    RayPrecomp pre = make_ray_precomp(origin, dir);
    // Boxes are padded by the bound of the whole scene's (intersect.glsl box_padding), once per ray rather than per
    // box; in an instance's object space by that bound times the most its map stretches a distance.
    float world_pad = box_padding(origin, params.scene_min.xyz, params.scene_max.xyz);
    float pad = world_pad;
    vec3 inv_dir = make_safe_inverse_dir(dir, pad);
    // Child words (take_child_word): the tree's measured bound (wide_bvh.h measure_stack_bound), one more for the
    // speculative descent's entry pushed back (below), and a last one that takes unpushed stores.
    uint stack[TRAVERSAL_STACK_SIZE + 2u];
    uint leaf_word = INVALID_INDEX;  // a leaf kept aside by the speculative descent
    uint stack_size = 0u;
    uint index = 0u;  // the root node
    uint count = 0u;
    vec3 origin_normal = origin_triangle != INVALID_INDEX ? normalize(triangle_normal(load_triangle_positions(origin_triangle)))
                                                          : vec3(0.0f);
    uint best_source = INVALID_INDEX;  // the best hit's TrianglePositions.source_index (tie-break)
    // A candidate hit waiting for its coverage (EFFECT_ALPHA): triangle INVALID_INDEX when none.
    TraceHit candidate;
    candidate.triangle = INVALID_INDEX;
    uint candidate_source = INVALID_INDEX;
    bool finished = false;
    while (!finished) {  // once, and once more after each alpha-tested candidate
        while (true) {
            // Descend until this lane holds a leaf (of triangles or an instance), or finds nothing below (index
            // INVALID_INDEX, count 0); a lane that does not descend runs the step idle and changes nothing.
            bool descend = count == 0u && index != INVALID_INDEX;
            while (true) {
                BvhWideNode n = load_bvh_node(descend ? index : 0u);
                vec3 node_origin = vec3(n.origin_x, n.origin_y, n.origin_z);
                vec3 step = uintBitsToFloat((uvec3(n.exponents) >> uvec3(0u, 8u, 16u) & 0xffu) << 23u);
                uvec3 lo_q = uvec3(n.lo_x, n.lo_y, n.lo_z), hi_q = uvec3(n.hi_x, n.hi_y, n.hi_z);
                uint kinds = n.exponents >> WIDE_KIND_SHIFT | n.first_node >> WIDE_KIND_SHIFT << 8u;
                uint next_node = n.first_node & WIDE_MAX_FIRST_NODE, next_leaf = n.first_leaf;
                uint word_0 = take_child_word(kinds, next_node, next_leaf);
                uint word_1 = take_child_word(kinds, next_node, next_leaf);
                uint word_2 = take_child_word(kinds, next_node, next_leaf);
                uint word_3 = take_child_word(kinds, next_node, next_leaf);
                NodeFrame frame = make_node_frame(node_origin, step, origin, inv_dir, pad);
                uvec3 near_q = near_planes(frame, lo_q, hi_q), far_q = far_planes(frame, lo_q, hi_q);
                ChildEntry c0 = test_child(word_0, 0u, frame, near_q, far_q, best.t);
                ChildEntry c1 = test_child(word_1, 8u, frame, near_q, far_q, best.t);
                ChildEntry c2 = test_child(word_2, 16u, frame, near_q, far_q, best.t);
                ChildEntry c3 = test_child(word_3, 24u, frame, near_q, far_q, best.t);
                // Nearest first: a sorting network of five compare-exchanges (missed children sort last).
                order_entries(c0, c1);
                order_entries(c2, c3);
                order_entries(c0, c2);
                order_entries(c1, c3);
                order_entries(c1, c2);
                // The nearest is next; the other hit ones wait on the stack, farthest deepest.
                PUSH_ENTRY(c3, descend)
                PUSH_ENTRY(c2, descend)
                PUSH_ENTRY(c1, descend)
                // A lane that missed every child takes its next entry here rather than idle (masked) until every
                // lane of the SIMD group holds a leaf. The top entry is loaded whether or not it is taken.
                bool hit_any = descend && c0.entry < MISSED_CHILD;
                uint top = stack[max(stack_size, 1u) - 1u];
                // Speculative descent (Aila & Laine 2009, sec. 4): a lane that reaches its first leaf of triangles
                // keeps it aside and descends on from its next stack entry while other lanes still look for theirs,
                // instead of idling (masked: on lavapipe an idle lane costs as much as a working one). Inside an
                // instance it goes no lower in the stack than where the instance was entered: the leaf kept aside
                // is tested with the instance's ray. Closest hits do not depend on the order of the visits
                // (ties go by source index), so the hits keep their bits.
                uint floor_size = scene_has_instances && instance != INVALID_INDEX ? instance_base : 0u;
                bool postpone = hit_any && leaf_word == INVALID_INDEX && child_count(c0.word) != 0u &&
                                child_count(c0.word) != WIDE_INSTANCE_COUNT && stack_size > floor_size;
                leaf_word = postpone ? c0.word : leaf_word;
                bool below_floor_ok = leaf_word == INVALID_INDEX || stack_size > floor_size;
                bool pop = descend && (!hit_any || postpone) && stack_size > 0u && below_floor_ok;
                uint next = hit_any && !postpone ? c0.word : top;
                stack_size -= pop ? 1u : 0u;
                bool moved = (hit_any && !postpone) || pop;
                index = descend ? (moved ? child_index(next) : INVALID_INDEX) : index;
                count = descend ? (moved ? child_count(next) : 0u) : count;
                if (pop) {
                    LEAVE_INSTANCE_BELOW_BASE()
                }
                // Every lane still descending has a leaf aside (or none descends): test the leaves.
                descend = count == 0u && index != INVALID_INDEX;
                if (subgroupAll(!descend || leaf_word != INVALID_INDEX)) break;
            }
            // A leaf kept aside comes first; where its lane got to since waits on the stack, or, if that is a leaf of
            // triangles too, is tested in the same loop.
            uint second_index = 0u, second_count = 0u;
            if (leaf_word != INVALID_INDEX) {
                bool second_leaf = count != 0u && count != WIDE_INSTANCE_COUNT && !effect_on(EFFECT_ALPHA);
                second_index = second_leaf ? index : 0u;
                second_count = second_leaf ? count : 0u;
                if (index != INVALID_INDEX && !second_leaf) {
                    PUSH_WORD(index << WIDE_COUNT_BITS | count, true)
                }
                index = child_index(leaf_word);
                count = child_count(leaf_word);
                leaf_word = INVALID_INDEX;
            }
            // Entering an instance maps the ray into its mesh's space and descends on from the mesh's root. Here rather
            // than in the descent loop, where (masked, on lavapipe) it ran at every node step.
            if (scene_has_instances && count == WIDE_INSTANCE_COUNT) {
                Instance inst = move_instance(load_instance(index), time);
                instance = index;
                instance_base = stack_size;
                origin = map_point(inst.object_from_render_0, inst.object_from_render_1, inst.object_from_render_2,
                                   world_origin);
                dir = map_vector(inst.object_from_render_0, inst.object_from_render_1, inst.object_from_render_2,
                                 world_dir);
                pre = make_ray_precomp(origin, dir);
                pad = world_pad * max_axis_stretch(inst.object_from_render_0, inst.object_from_render_1,
                                                   inst.object_from_render_2);
                inv_dir = make_safe_inverse_dir(dir, pad);
                index = inst.root_node;
                count = 0u;
                continue;
            }
            bool tie_break = !any_hit && FH_TECHNIQUE_ON(TECHNIQUE_TIE_BREAK);
            for (uint k = 0u; k < count + second_count; ++k) {
                uint tri = k < count ? index + k : second_index + (k - count);
                TrianglePositions tp = load_triangle_positions(tri);
                bool have_hit = best.triangle != INVALID_INDEX;
                float limit = tie_break && have_hit ? next_float_up(best.t) : best.t;
                vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z), p1 = vec3(tp.p1_x, tp.p1_y, tp.p1_z);
                TriangleHit h = intersect_triangle(pre, p0, p1, vec3(tp.p2_x, tp.p2_y, tp.p2_z), limit);
                // intersect_triangle only reports t < limit: closer, or (tie-break) equal.
                if (h.hit == HIT_UNCERTAIN && is_same_surface(tri, tp, origin_triangle, origin_normal)) h.hit = 0u;
                bool take = h.hit != 0u && (!have_hit || h.t < best.t || tp.source_index < best_source);
                if (effect_on(EFFECT_ALPHA) && take && (tp.flags & TRIANGLE_ALPHA_TESTED) != 0u) {
                    candidate.t = h.t;
                    candidate.triangle = tri;
                    candidate.b1 = h.b1;
                    candidate.b2 = h.b2;
                    candidate_source = tp.source_index;
                    // Resume at the leaf's next triangle, or at the next stack entry when it has none.
                    count -= k + 1u;
                    index = count > 0u ? tri + 1u : INVALID_INDEX;
                    break;
                }
                if (take) {
                    best.t = h.t;
                    best.triangle = tri;
                    best.b1 = h.b1;
                    best.b2 = h.b2;
                    best.instance = instance;
                    best_source = tp.source_index;
                    if (any_hit) {
                        stack_size = 0u;  // nothing more to visit
                        break;
                    }
                }
            }
            if (effect_on(EFFECT_ALPHA) && candidate.triangle != INVALID_INDEX) break;
            // A finished lane stays, idle (no node, no leaf), until every lane still here has finished.
            finished = stack_size == 0u;
            if (!finished) {
                POP_ENTRY()
            }
            index = finished ? INVALID_INDEX : index;
            count = finished ? 0u : count;
            if (subgroupAll(finished)) break;
        }
        if (effect_on(EFFECT_ALPHA) && candidate.triangle != INVALID_INDEX) {
            if (is_surface_present(candidate.triangle, candidate.b1, candidate.b2, alpha_seed)) {
                best.t = candidate.t;
                best.triangle = candidate.triangle;
                best.b1 = candidate.b1;
                best.b2 = candidate.b2;
                best.instance = instance;
                best_source = candidate_source;
                if (any_hit) return best;
            }
            candidate.triangle = INVALID_INDEX;
        }
        // Without EFFECT_ALPHA nothing suspends traversal: one pass, and the compiler drops this loop.
        if (!effect_on(EFFECT_ALPHA)) break;
    }
    return best;
}
#undef PUSH_ENTRY
#undef POP_ENTRY
#undef LEAVE_INSTANCE_BELOW_BASE
#endif
