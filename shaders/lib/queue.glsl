// Appending to queues with one atomic per subgroup instead of one per invocation (measured ~3x faster on
// lavapipe). Correct under any divergence: ballot, elect and broadcast all act on the same active set.
#ifndef FH_QUEUE_GLSL
#define FH_QUEUE_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

// Sets `slot` to a unique index in the queue whose length is `counter` for every active invocation with
// `wants` true. A macro because GLSL cannot pass a buffer member to a function by reference.
#define PUSH_TO_QUEUE(counter, wants, slot)                                    \
    {                                                                          \
        uvec4 ballot_ = subgroupBallot(wants);                                 \
        uint total_ = subgroupBallotBitCount(ballot_);                         \
        uint base_ = 0u;                                                       \
        if (subgroupElect() && total_ > 0u) base_ = atomicAdd(counter, total_); \
        base_ = subgroupBroadcastFirst(base_);                                 \
        slot = base_ + subgroupBallotExclusiveBitCount(ballot_);               \
    }

// Adds `value` (summed over the active invocations) to `counter` with one atomic per subgroup.
#define COUNT_IN_SUBGROUP(counter, value)                                      \
    {                                                                          \
        uint sum_ = subgroupAdd(value);                                        \
        if (subgroupElect() && sum_ > 0u) atomicAdd(counter, sum_);            \
    }

// Adds the number of active invocations with `condition` true to `counter`, with one atomic per subgroup: a ballot's
// bit count, where subgroupAdd of 0 or 1 is a loop over the lanes on lavapipe.
#define COUNT_TRUE_IN_SUBGROUP(counter, condition)                             \
    {                                                                          \
        uint true_ = subgroupBallotBitCount(subgroupBallot(condition));        \
        if (subgroupElect() && true_ > 0u) atomicAdd(counter, true_);          \
    }

// The counters at the start of a wave, all 14 words of QueueCounters (layout.h; every field's offset checked by
// test_layout, since these stores name the words by position) in
// four vector stores: `total` rays in queue 0 and its extend dispatch, `shadow_count` shadow rays (light tracing
// hands every path's first splat to connect), everything else 0 and the unused dispatch sizes 1. Called by the
// wave's first invocation only, but on lavapipe every SIMD group runs each store's loop over its lanes, masked, so
// four store instructions cost each group far less than one per word.
layout(std430, binding = BINDING_COUNTERS) coherent writeonly buffer CounterQuads { uvec4 counter_quads[]; };
layout(std430, binding = BINDING_COUNTERS) coherent writeonly buffer CounterPairs { uvec2 counter_pairs[]; };
void reset_counters(uint total, uint shadow_count) {
    uint groups = (total + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    counter_quads[0] = uvec4(total, 0u, shadow_count, 0u);  // ray_count[0], [1], shadow_count, shadow_count_active
    counter_quads[1] = uvec4(groups, 1u, 1u, 0u);          // extend_args, connect_args.x (advance sets it)
    counter_quads[2] = uvec4(1u, 1u, 0u, 0u);              // connect_args.y, .z, nonfinite_samples, escaped_rays
    counter_pairs[6] = uvec2(0u, 0u);                      // traced_rays, traced_shadow_rays
}
#endif
