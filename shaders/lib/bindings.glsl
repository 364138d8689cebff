// Declares every storage buffer of the wavefront renderer (bindings from shared/layout.h) for the stages.
#ifndef FH_BINDINGS_GLSL
#define FH_BINDINGS_GLSL
#include "../shared/layout.h"

layout(std430, binding = BINDING_PARAMS) readonly buffer ParamsBuffer { FrameParams params; };
layout(std430, binding = BINDING_BVH_NODES) readonly buffer NodeBuffer { BvhNode nodes[]; };
layout(std430, binding = BINDING_TRI_POSITIONS) readonly buffer PositionBuffer { TrianglePositions tri_positions[]; };
layout(std430, binding = BINDING_TRI_SHADING) readonly buffer ShadingBuffer { TriangleShading tri_shading[]; };
layout(std430, binding = BINDING_MATERIALS) readonly buffer MaterialBuffer { Material materials[]; };
layout(std430, binding = BINDING_EMITTERS) readonly buffer EmitterBuffer { Emitter emitters[]; };
layout(std430, binding = BINDING_COUNTERS) coherent buffer CounterBuffer { QueueCounters counters; };
layout(std430, binding = BINDING_PATHS) buffer PathBuffer { PathState paths[]; };
layout(std430, binding = BINDING_RAYS) buffer RayBuffer { RayItem rays[]; };
layout(std430, binding = BINDING_HITS) buffer HitBuffer { HitItem hits[]; };
layout(std430, binding = BINDING_SHADOW_RAYS) buffer ShadowBuffer { ShadowRayItem shadow_rays[]; };
layout(std430, binding = BINDING_FILM) buffer FilmBuffer { FilmPixel film[]; };

layout(std140, binding = BINDING_BVH_NODES_UNIFORM) uniform NodeUniforms { BvhNode uniform_nodes[UNIFORM_NODE_CAPACITY]; };
layout(std140, binding = BINDING_TRI_POSITIONS_UNIFORM) uniform PositionUniforms {
    TrianglePositions uniform_tri_positions[UNIFORM_TRIANGLE_CAPACITY];
};

layout(push_constant) uniform PushBlock { StagePush push; };

vec3 load_triangle_vertex(uint triangle, uint corner) {
    TrianglePositions t = tri_positions[triangle];
    if (corner == 0u) return vec3(t.p0_x, t.p0_y, t.p0_z);
    if (corner == 1u) return vec3(t.p1_x, t.p1_y, t.p1_z);
    return vec3(t.p2_x, t.p2_y, t.p2_z);
}

// Index of a ray in the queue of the given depth parity (two queues share one buffer).
uint ray_slot(uint parity, uint index) { return parity * params.wave_capacity + index; }

#endif
