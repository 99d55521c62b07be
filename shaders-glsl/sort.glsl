// Shared by the radix-sort passes (crates/renderer/src/passes/sort.rs): an LSD radix sort of (key, value) u32
// pairs, 4-bit digits, one histogram / scan / scatter triple of dispatches per digit.
#ifndef LEAKLESS_SORT_GLSL
#define LEAKLESS_SORT_GLSL

// Mirrored in crates/renderer/src/passes/sort.rs (WORKGROUP_SIZE, ITEMS_PER_THREAD); the workgroup size is
// checked against reflection when the pipelines are built.
#define SORT_WORKGROUP_SIZE 256
#define SORT_ITEMS 16
// One workgroup of the histogram and scatter passes handles SORT_BLOCK consecutive elements,
// thread t the SORT_ITEMS elements from t * SORT_ITEMS on (thread-major, so that ranking by
// (thread, item) is ranking by element order: what makes the scatter stable).
const uint SORT_BLOCK = SORT_WORKGROUP_SIZE * SORT_ITEMS;
const uint SORT_RADIX = 16u;
// The digit of an element the workgroup does not hold (past the end): matches no digit.
const uint SORT_NO_DIGIT = SORT_RADIX;

// Parameters of one digit pass. `histograms` holds SORT_RADIX * group_count counts,
// digit-major: the count of digit d in workgroup g is at d * group_count + g.
#define SORT_PARAMS_BLOCK layout(push_constant) uniform SortParams { \
    uint len; \
    uint shift; \
    uint key_limit; \
    uint group_count; \
} params

// The digit a pass sorts by. Keys at or above key_limit (2^key_bits, or 0xFFFFFFFF for 32-bit
// keys) are all ordered as key_limit itself: after every valid key, among themselves in
// input order. That is how the 0xFFFFFFFF sentinel of invalid pixels sorts last.
uint sortDigit(uint key, uint key_limit, uint shift) {
    return (min(key, key_limit) >> shift) & (SORT_RADIX - 1u);
}

// A thread's digit counts, packed two per word, 16 bits each: digit d in word d / 2, bits
// 16 * (d % 2). Any sum of them over a workgroup is at most SORT_BLOCK per digit, below 2^16,
// so packed sums never carry from one digit's field into the next.
const uint SORT_WORDS = SORT_RADIX / 2u;

// Adds one element of digit `digit` to the packed counts (SORT_NO_DIGIT adds nothing). The
// word is chosen by a loop of selects, not by a dynamic index, so `packed` stays in registers.
void sortCount(inout uint packed[SORT_WORDS], uint digit) {
    uint increment = 1u << ((digit & 1u) * 16u);
    for (uint w = 0u; w < SORT_WORDS; ++w) {
        packed[w] += (digit >> 1u) == w ? increment : 0u;
    }
}

// The count of `digit` in a packed word holding it.
uint sortField(uint word, uint digit) {
    return (word >> ((digit & 1u) * 16u)) & 0xFFFFu;
}

// Shared-memory scans and sums over the threads of a workgroup are done on columns of
// SORT_WORKGROUP_SIZE rows (one per thread), split into SORT_SEGMENTS segments of
// SORT_SEGMENT_LENGTH rows each handled by one thread: SORT_WORDS * SORT_SEGMENTS must equal
// SORT_WORKGROUP_SIZE (one thread per segment of each word column).
const uint SORT_SEGMENT_LENGTH = 8u;
const uint SORT_SEGMENTS = SORT_WORKGROUP_SIZE / SORT_SEGMENT_LENGTH;

#endif
