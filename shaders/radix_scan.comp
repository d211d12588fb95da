// The exclusive prefix sum of an array of counts, in place (src/gpu/gpu_scan.h:
// the radix sort's histograms, step 2 of each pass, and the slices' tile
// counts), as brick_scan.comp sums its flags. Three phases (uPhase):
//   0: each work group sums its 1024 counts into blockSums
//   1: one work group scans blockSums; where asked (uWriteTotal), writes
//      the total to `kept` (the radix sort's first pass: the pairs it keeps)
//   2: each work group rescans its counts and adds its block's offset.
layout(local_size_x = 256) in;

layout(std430, binding = kSortHistogramBinding) buffer Histogram { uint counts[]; };
layout(std430, binding = kSortBlockSumsBinding) buffer BlockSums { uint blockSums[]; };
layout(std430, binding = kSortKeptBinding) buffer Kept { uint kept; };

uniform uint uCounts;
uniform uint uBlockCount;
uniform int uPhase;
uniform int uWriteTotal;

const uint kPerThread = 4u;
const uint kPerGroup = 1024u;
shared uint partial[256];

// Exclusive scan of `partial` across the work group (Hillis-Steele); returns the group total.
uint groupScan(uint value) {
    uint lid = gl_LocalInvocationID.x;
    partial[lid] = value;
    barrier();
    for (uint offset = 1u; offset < 256u; offset <<= 1) {
        uint add = lid >= offset ? partial[lid - offset] : 0u;
        barrier();
        partial[lid] += add;
        barrier();
    }
    uint total = partial[255];
    uint exclusive = partial[lid] - value;
    barrier();
    partial[lid] = exclusive;
    barrier();
    return total;
}

void main() {
    uint lid = gl_LocalInvocationID.x;
    if (uPhase == 1) {
        uint carry = 0u;
        for (uint base = 0u; base < uBlockCount; base += 256u * kPerThread) {
            uint v[kPerThread];
            uint sum = 0u;
            for (uint j = 0u; j < kPerThread; ++j) {
                uint idx = base + lid * kPerThread + j;
                v[j] = idx < uBlockCount ? blockSums[idx] : 0u;
                sum += v[j];
            }
            uint total = groupScan(sum);
            uint running = carry + partial[lid];
            for (uint j = 0u; j < kPerThread; ++j) {
                uint idx = base + lid * kPerThread + j;
                if (idx < uBlockCount) blockSums[idx] = running;
                running += v[j];
            }
            carry += total;
        }
        if (lid == 0u && uWriteTotal != 0) kept = carry;
        return;
    }

    for (uint group = gl_WorkGroupID.x; group < uBlockCount; group += gl_NumWorkGroups.x) {
        uint first = group * kPerGroup + lid * kPerThread;
        uint v[kPerThread];
        uint sum = 0u;
        for (uint j = 0u; j < kPerThread; ++j) {
            uint idx = first + j;
            v[j] = idx < uCounts ? counts[idx] : 0u;
            sum += v[j];
        }
        uint total = groupScan(sum);
        if (uPhase == 0) {
            if (lid == 0u) blockSums[group] = total;
            continue;
        }
        uint running = blockSums[group] + partial[lid];
        for (uint j = 0u; j < kPerThread; ++j) {
            uint idx = first + j;
            if (idx < uCounts) counts[idx] = running;
            running += v[j];
        }
    }
}
