// Counters and slot reservations shared by many threads, optionally combined per subgroup.
//
// With SUBGROUP_COUNTERS (a specialization constant the device tuning sets: off on CPUs, on
// GPUs that have subgroup ballot and arithmetic), the first active lane of a subgroup makes
// one atomic for all its active lanes: a GPU's hot global counters then see one atomic per
// subgroup instead of one per thread. Totals are the same either way; reserved slots are
// handed out in another order, which nothing downstream depends on (the gather's sums are
// order-independent).
//
// Atomics take a buffer member, not a function argument, hence macros. naga, which crates/renderer/build.rs
// reflects buffer layouts with, parses no subgroup operation: under LEAKLESS_REFLECTION (a
// twin compiled for reflection only) the subgroup branches are left out.
#ifndef LEAKLESS_COUNTERS_GLSL
#define LEAKLESS_COUNTERS_GLSL
#ifdef LEAKLESS_REFLECTION
#define SUBGROUP_COUNTERS false
#define subgroupBallot(X) uvec4(0u)
#define subgroupBallotBitCount(X) 0u
#define subgroupBallotExclusiveBitCount(X) 0u
#define subgroupElect() false
#define subgroupBroadcastFirst(X) (X)
#define subgroupAdd(X) (X)
#ifndef subgroupMax
#define subgroupMax(X) (X)
#endif
#else
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
layout(constant_id = 1) const bool SUBGROUP_COUNTERS = false;
#endif

// SLOT = atomicAdd(COUNTER, 1u): the subgroup's first active lane reserves a slot for every
// active lane and each lane takes its rank among them. The lanes active at the ballot must be
// those at the broadcast after the elected lane's branch, as on every driver that combines
// atomics this way; the GPU report checks it where it matters, on the GPU: every tuning variant,
// subgroup counters on and off, must store and list the same photons.
#define RESERVE_ONE(COUNTER, SLOT)                                                           \
    if (SUBGROUP_COUNTERS) {                                                                 \
        uvec4 ballot_ = subgroupBallot(true);                                                \
        uint base_ = 0u;                                                                     \
        if (subgroupElect()) {                                                               \
            base_ = atomicAdd(COUNTER, subgroupBallotBitCount(ballot_));                     \
        }                                                                                    \
        SLOT = subgroupBroadcastFirst(base_) + subgroupBallotExclusiveBitCount(ballot_);     \
    } else {                                                                                 \
        SLOT = atomicAdd(COUNTER, 1u);                                                       \
    }

// COUNTER = max(COUNTER, VALUE), one atomic a subgroup where the subgroup combines.
#define MAX_COUNT(COUNTER, VALUE)                                                            \
    if (SUBGROUP_COUNTERS) {                                                                 \
        uint most_ = subgroupMax(VALUE);                                                     \
        if (subgroupElect()) {                                                               \
            atomicMax(COUNTER, most_);                                                       \
        }                                                                                    \
    } else {                                                                                 \
        atomicMax(COUNTER, VALUE);                                                           \
    }

// COUNTER += VALUE (32-bit, wrapping alike either way); nothing is added where nothing counts.
#define ADD_COUNT(COUNTER, VALUE)                                                            \
    if (SUBGROUP_COUNTERS) {                                                                 \
        uint total_ = subgroupAdd(VALUE);                                                    \
        if (subgroupElect() && total_ != 0u) {                                               \
            atomicAdd(COUNTER, total_);                                                      \
        }                                                                                    \
    } else if ((VALUE) != 0u) {                                                              \
        atomicAdd(COUNTER, VALUE);                                                           \
    }

// (LO, HI) += VALUE, a 64-bit total kept as two words (no 64-bit atomics needed). A
// subgroup's sum is taken in 16-bit halves, so no 32-bit partial sum can overflow.
#define ADD64(LO, HI, VALUE)                                                                 \
    if (SUBGROUP_COUNTERS) {                                                                 \
        uint64_t total_ = (uint64_t(subgroupAdd((VALUE) >> 16u)) << 16u) + uint64_t(subgroupAdd((VALUE) & 0xffffu)); \
        if (subgroupElect()) {                                                               \
            uint low_ = uint(total_);                                                        \
            uint high_ = uint(total_ >> 32u);                                                \
            uint before_ = atomicAdd(LO, low_);                                              \
            high_ += before_ + low_ < before_ ? 1u : 0u;                                     \
            if (high_ != 0u) {                                                               \
                atomicAdd(HI, high_);                                                        \
            }                                                                                \
        }                                                                                    \
    } else {                                                                                 \
        uint before_ = atomicAdd(LO, VALUE);                                                 \
        if (before_ + (VALUE) < before_) {                                                   \
            atomicAdd(HI, 1u);                                                               \
        }                                                                                    \
    }

#endif
