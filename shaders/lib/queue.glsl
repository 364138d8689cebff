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
#endif
