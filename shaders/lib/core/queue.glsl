// Appending to queues and counting with one atomic per workgroup or subgroup instead of one per invocation (one per
// subgroup measured ~3x faster on lavapipe than one per invocation). Correct under any divergence: ballot, elect and
// broadcast all act on the same active set. A macro because GLSL cannot pass a buffer member to a function by reference.
#ifndef FH_QUEUE_GLSL
#define FH_QUEUE_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

// What a path-vertex stage (shade, light_shade) appends at its end, with one atomic per counter and workgroup instead
// of per subgroup: its continuation ray to queue `ray_counter` (slot `ray_slot`), its shadow ray to queue
// `shadow_counter` (slot `shadow_slot`), and whether its ray had escaped the scene to the count `escaped_counter`.
// Every invocation of the workgroup must reach it (it has barriers). Each subgroup's counts go to shared memory, the
// first invocation adds the workgroup's totals to the counters, and each subgroup's slots follow those of the
// subgroups before it. On lavapipe the two threads' atomics on the counters' cache line took about 6% of a render's
// time with one atomic per subgroup (tests/bench/RESULTS.md "Speed"). Slots within a queue follow no fixed order: an item carries its
// path, whose numbers depend on its pixel, sample and depth, not on its slot, so the images do not depend on it.
shared uvec4 queue_subgroup_counts_[WORKGROUP_SIZE];  // per subgroup: rays, shadow rays, escaped rays
shared uvec2 queue_group_bases_;
#define PUSH_VERTEX_RESULTS_IN_WORKGROUP(ray_counter, push_ray, ray_slot, shadow_counter, push_shadow, shadow_slot,   \
                                         escaped_counter, escaped)                                                 \
    {                                                                                                              \
        uvec4 ballot_ray_ = subgroupBallot(push_ray), ballot_shadow_ = subgroupBallot(push_shadow);                \
        uvec4 mine_ = uvec4(subgroupBallotBitCount(ballot_ray_), subgroupBallotBitCount(ballot_shadow_),           \
                            subgroupBallotBitCount(subgroupBallot(escaped)), 0u);                                  \
        if (subgroupElect()) queue_subgroup_counts_[gl_SubgroupID] = mine_;                                        \
        barrier();                                                                                                 \
        if (gl_LocalInvocationIndex == 0u) {                                                                       \
            uvec4 total_ = uvec4(0u);                                                                              \
            for (uint s_ = 0u; s_ < gl_NumSubgroups; ++s_) total_ += queue_subgroup_counts_[s_];                   \
            queue_group_bases_ = uvec2(total_.x > 0u ? atomicAdd(ray_counter, total_.x) : 0u,                      \
                                       total_.y > 0u ? atomicAdd(shadow_counter, total_.y) : 0u);                 \
            if (total_.z > 0u) atomicAdd(escaped_counter, total_.z);                                               \
        }                                                                                                          \
        /* The slots of the subgroups before this one come first. */                                               \
        uvec4 before_ = uvec4(0u);                                                                                 \
        for (uint s_ = 0u; s_ < gl_SubgroupID; ++s_) before_ += queue_subgroup_counts_[s_];                        \
        barrier();                                                                                                 \
        uvec2 bases_ = queue_group_bases_;                                                                         \
        ray_slot = bases_.x + before_.x + subgroupBallotExclusiveBitCount(ballot_ray_);                            \
        shadow_slot = bases_.y + before_.y + subgroupBallotExclusiveBitCount(ballot_shadow_);                      \
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
