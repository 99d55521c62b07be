#version 460
// Radix sort, step 2 of a digit pass: one workgroup turns the digit-major counts into
// exclusive prefix sums, in place. The count of digit d in workgroup g becomes the first
// output position of those elements: all smaller digits everywhere, plus digit d in the
// workgroups before g. The workgroup walks the counts in tiles of SORT_WORKGROUP_SIZE *
// SCAN_ITEMS, carrying the running total from tile to tile, so it handles any number of
// counts; its cost grows linearly with them (see MAX_LEN in crates/renderer/src/passes/sort.rs).
#include "sort.glsl"

layout(local_size_x = SORT_WORKGROUP_SIZE) in;

SORT_PARAMS_BLOCK;
layout(set = 1, binding = 0, std430) buffer Histograms { uint data[]; } histograms;

#define SCAN_ITEMS 16
const uint SCAN_TILE = SORT_WORKGROUP_SIZE * SCAN_ITEMS;
// The thread sums are scanned by RAKE_THREADS threads of RAKE_LENGTH sums each, then their
// RAKE_THREADS totals by one thread.
const uint RAKE_LENGTH = 16u;
const uint RAKE_THREADS = SORT_WORKGROUP_SIZE / RAKE_LENGTH;

shared uint s_sums[SORT_WORKGROUP_SIZE];
shared uint s_rakes[RAKE_THREADS];
shared uint s_tile_total;

void main() {
    uint t = gl_LocalInvocationID.x;
    uint count = SORT_RADIX * params.group_count;
    uint carry = 0u;
    for (uint base = 0u; base < count; base += SCAN_TILE) {
        uint first = base + t * SCAN_ITEMS;
        uint v[SCAN_ITEMS];
        uint sum = 0u;
        for (uint k = 0u; k < SCAN_ITEMS; ++k) {
            uint i = first + k;
            v[k] = i < count ? histograms.data[i] : 0u;
            sum += v[k];
        }
        s_sums[t] = sum;
        barrier();
        if (t < RAKE_THREADS) {
            uint run = 0u;
            for (uint j = 0u; j < RAKE_LENGTH; ++j) {
                uint x = s_sums[t * RAKE_LENGTH + j];
                s_sums[t * RAKE_LENGTH + j] = run;
                run += x;
            }
            s_rakes[t] = run;
        }
        barrier();
        if (t == 0u) {
            uint run = 0u;
            for (uint j = 0u; j < RAKE_THREADS; ++j) {
                uint x = s_rakes[j];
                s_rakes[j] = run;
                run += x;
            }
            s_tile_total = run;
        }
        barrier();
        uint prefix = carry + s_rakes[t / RAKE_LENGTH] + s_sums[t];
        for (uint k = 0u; k < SCAN_ITEMS; ++k) {
            uint i = first + k;
            if (i < count) {
                histograms.data[i] = prefix;
            }
            prefix += v[k];
        }
        carry += s_tile_total;
        // Every thread has read this tile's shared sums before the next tile overwrites them.
        barrier();
    }
}
