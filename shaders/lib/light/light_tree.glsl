// The light tree (`--light-sampler tree`, EFFECT_LIGHT_TREE; host: scene/light/light_tree.h): next-event estimation walks
// from the root to one light, at each node taking a child with probability proportional to its importance at the
// shading point, a conservative bound on the light that child's lights can send there (Conty Estevez & Kulla 2018;
// pbrt-v4 LightBounds::Importance). The probability of the light reached is the product of the choices. A ray that
// the BSDF sent and that hits an emitter needs that probability at the vertex it left: the walk runs again, along the
// leaf's stored path, from the same point and normal, which shade stores per path (pack_light_point), so the two
// weights of MIS see the very same number.
//
// Written in the GLSL subset that also compiles as C++ (lib/core/cpp_compat.h): tests/unit/scene/test_light_tree.cpp checks the
// walk's choices against the probability it reports. The includer provides load_light_tree_node and params.
#ifndef FH_LIGHT_TREE_GLSL
#define FH_LIGHT_TREE_GLSL

// Where NEE stands: the point, and the normal whose cosine bounds what a light can add there.
const uint LIGHT_POINT_NO_NORMAL = 0u;  // no cosine bound (both hemispheres, no normal known)
const uint LIGHT_POINT_ONE_SIDED = 1u;  // only lights above the normal's side can add (a surface that only reflects)
const uint LIGHT_POINT_TWO_SIDED = 2u;  // either side (a surface that also transmits)

struct LightTreePoint {
    vec3 p;
    vec3 n;     // unit, or unused with LIGHT_POINT_NO_NORMAL
    uint kind;  // LIGHT_POINT_*
};

float sign_not_zero(float x) { return x >= 0.0f ? 1.0f : -1.0f; }

// The point's position bits and its normal in 32 bits: octahedral, 15 bits per coordinate, the kind in bits 30-31.
uvec4 pack_light_point(vec3 p, vec3 n, uint kind) {
    float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    vec2 o = l1 > 0.0f ? vec2(n.x, n.y) / l1 : vec2(0.0f);
    if (n.z < 0.0f) o = vec2((1.0f - abs(o.y)) * sign_not_zero(o.x), (1.0f - abs(o.x)) * sign_not_zero(o.y));
    uint qx = uint(clamp(o.x * 0.5f + 0.5f, 0.0f, 1.0f) * 32767.0f + 0.5f);
    uint qy = uint(clamp(o.y * 0.5f + 0.5f, 0.0f, 1.0f) * 32767.0f + 0.5f);
    return uvec4(floatBitsToUint(p.x), floatBitsToUint(p.y), floatBitsToUint(p.z), qx | (qy << 15u) | (kind << 30u));
}

LightTreePoint unpack_light_point(uvec4 w) {
    LightTreePoint q;
    q.p = vec3(uintBitsToFloat(w.x), uintBitsToFloat(w.y), uintBitsToFloat(w.z));
    vec2 o = vec2(float(w.w & 32767u), float((w.w >> 15u) & 32767u)) * (2.0f / 32767.0f) - 1.0f;
    vec3 n = vec3(o.x, o.y, 1.0f - abs(o.x) - abs(o.y));
    if (n.z < 0.0f) n = vec3((1.0f - abs(o.y)) * sign_not_zero(o.x), (1.0f - abs(o.x)) * sign_not_zero(o.y), n.z);
    q.n = normalize(n);
    q.kind = w.w >> 30u;
    return q;
}

// The point as NEE and the later hit both see it: through the packing, so both use the same bits.
LightTreePoint make_light_point(vec3 p, vec3 n, uint kind) { return unpack_light_point(pack_light_point(p, n, kind)); }

// cos(max(a - b, 0)) and sin(max(a - b, 0)) from the sines and cosines of angles a, b in [0, pi].
float cos_minus_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
float sin_minus_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}
float sqrt_clamped(float x) { return sqrt(max(x, 0.0f)); }

// A bound on what the node's lights send to q, up to a common factor: power over squared distance (to the box's
// centre, at least its half diagonal), times the cosine of the smallest angle the node's emission cone and the
// directions towards q can make, times the cosine at q of the nearest direction into the box. 0 only where none of
// the node's lights can reach q's side. At most 1e37, so that two sum without overflow.
float light_importance(LightTreeNode node, LightTreePoint q) {
    vec3 lo = vec3(node.min_x, node.min_y, node.min_z);
    vec3 hi = vec3(node.max_x, node.max_y, node.max_z);
    vec3 diagonal = hi - lo;
    float radius2 = 0.25f * dot(diagonal, diagonal);  // of the box's bounding sphere
    vec3 to_point = q.p - 0.5f * (lo + hi);
    float d2 = dot(to_point, to_point);
    float clamped_d2 = max(max(d2, radius2), 1e-30f);
    float importance = node.power / clamped_d2;
    if (d2 <= radius2) return min(importance, 1e37f);  // q within the bounding sphere: any direction
    vec3 wi = to_point * inversesqrt(d2);              // from the lights towards q
    float sin_b2 = radius2 / d2;                       // the sphere subtends theta_b at q
    float sin_b = sqrt(sin_b2);
    float cos_b = sqrt_clamped(1.0f - sin_b2);
    float cos_w = dot(vec3(node.axis_x, node.axis_y, node.axis_z), wi);
    if ((node.flags & LIGHT_NODE_TWO_SIDED) != 0u) cos_w = abs(cos_w);
    float sin_w = sqrt_clamped(1.0f - cos_w * cos_w);
    float sin_o = sqrt_clamped(1.0f - node.cos_theta_o * node.cos_theta_o);
    float cos_x = cos_minus_clamped(sin_w, cos_w, sin_o, node.cos_theta_o);
    float sin_x = sin_minus_clamped(sin_w, cos_w, sin_o, node.cos_theta_o);
    float cos_p = cos_minus_clamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= node.cos_theta_e) return 0.0f;
    importance *= cos_p;
    if (q.kind != LIGHT_POINT_NO_NORMAL) {
        float cos_i = -dot(wi, q.n);  // towards the lights, against q's normal
        if (q.kind == LIGHT_POINT_TWO_SIDED) cos_i = abs(cos_i);
        float sin_i = sqrt_clamped(1.0f - cos_i * cos_i);
        importance *= max(cos_minus_clamped(sin_i, cos_i, sin_b, cos_b), 0.0f);
    }
    return min(max(importance, 0.0f), 1e37f);
}

struct LightTreeWalk {
    uint entry;  // the Emitter entry reached (valid when pdf > 0)
    float pdf;   // the probability of reaching it from q (0: no light of the tree can reach q)
    float u;     // what is left of u: uniform in [0, 1) again (sample_light_connection reuses it)
};

// From the root to a leaf: by u (follow_path false), or along `path` (bit k: the second child at level k), which
// gives the probability that u would have led there. One function for both, so that both multiply the same factors.
LightTreeWalk walk_light_tree(LightTreePoint q, float u, uint path, bool follow_path) {
    LightTreeWalk walk;
    walk.entry = 0u;
    walk.pdf = 1.0f;
    walk.u = u;
    LightTreeNode node = load_light_tree_node(0u);
    for (uint level = 0u; level < LIGHT_TREE_MAX_DEPTH && (node.flags & LIGHT_NODE_LEAF) == 0u; ++level) {
        LightTreeNode first = load_light_tree_node(node.child0);
        LightTreeNode second = load_light_tree_node(node.child1);
        float i0 = light_importance(first, q);
        float i1 = light_importance(second, q);
        if (!(i0 + i1 > 0.0f)) {
            walk.pdf = 0.0f;
            return walk;
        }
        float p0 = i0 / (i0 + i1);
        bool take_second = follow_path ? ((path >> level) & 1u) != 0u : !(walk.u < p0);
        if (take_second) {
            walk.pdf *= 1.0f - p0;
            walk.u = min((walk.u - p0) / (1.0f - p0), ONE_BELOW_ONE);
            node = second;
        } else {
            walk.pdf *= p0;
            walk.u = min(walk.u / p0, ONE_BELOW_ONE);
            node = first;
        }
    }
    walk.entry = node.emitter;
    if ((node.flags & LIGHT_NODE_LEAF) == 0u || !(walk.pdf > 0.0f)) walk.pdf = 0.0f;
    return walk;
}

// NEE picks the tree with this probability, and each light outside it (the environment, directional lights) with the
// same (pbrt-v4's rule: one share each).
float light_tree_share() { return 1.0f / float(params.emitter_count - params.light_tree_lights + 1u); }

// The probability that NEE at q picks Emitter entry `entry` of the tree (entry < params.light_tree_lights).
float tree_light_pick_pdf(LightTreePoint q, uint entry) {
    LightTreeNode leaf = load_light_tree_node(params.light_tree_lights - 1u + entry);
    return light_tree_share() * walk_light_tree(q, 0.5f, leaf.child0, true).pdf;
}

#endif
