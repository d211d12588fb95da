// Resolve pass 2: exclusive prefix sum, in place, of each brick slot's
// (kept, active voxels) from brick_resolve.comp's count pass, giving each kept
// brick its header index and its first voxel in the packed output; the totals
// (kept bricks, active voxels) go to totals[0]. Phases (uPhase), as in
// brick_scan.comp:
//   0: each work group sums its 1024 slots into blockSums
//   1: one work group scans blockSums and writes the totals
//   2: each work group rescans its slots and adds its block offset
layout(local_size_x = 256) in;

layout(std430, binding = kResolvePlacesBinding) buffer Places { uvec2 places[]; };
layout(std430, binding = kResolveBlockSumsBinding) buffer BlockSums { uvec2 blockSums[]; };
layout(std430, binding = kResolveTotalsBinding) writeonly buffer Totals { uvec2 totals[]; };

uniform uint uBrickCount;
uniform uint uBlockCount;
uniform int uPhase;

const uint kPerThread = 4u;
const uint kPerGroup = 1024u;
shared uvec2 partial[256];

// Exclusive scan of `partial` across the work group (Hillis-Steele); returns the group total.
uvec2 groupScan(uvec2 value) {
    uint lid = gl_LocalInvocationID.x;
    partial[lid] = value;
    barrier();
    for (uint offset = 1u; offset < 256u; offset <<= 1) {
        uvec2 add = lid >= offset ? partial[lid - offset] : uvec2(0u);
        barrier();
        partial[lid] += add;
        barrier();
    }
    uvec2 total = partial[255];
    uvec2 exclusive = partial[lid] - value;
    barrier();
    partial[lid] = exclusive;
    barrier();
    return total;
}

void main() {
    uint lid = gl_LocalInvocationID.x;
    if (uPhase == 1) {
        uvec2 carry = uvec2(0u);
        for (uint base = 0u; base < uBlockCount; base += 256u * kPerThread) {
            uvec2 v[4];
            uvec2 sum = uvec2(0u);
            for (uint j = 0u; j < kPerThread; ++j) {
                uint idx = base + lid * kPerThread + j;
                v[j] = idx < uBlockCount ? blockSums[idx] : uvec2(0u);
                sum += v[j];
            }
            uvec2 total = groupScan(sum);
            uvec2 running = carry + partial[lid];
            for (uint j = 0u; j < kPerThread; ++j) {
                uint idx = base + lid * kPerThread + j;
                if (idx < uBlockCount) blockSums[idx] = running;
                running += v[j];
            }
            carry += total;
        }
        if (lid == 0u) totals[0] = carry;
        return;
    }

    uint group = gl_WorkGroupID.x;
    uint first = group * kPerGroup + lid * kPerThread;
    uvec2 v[4];
    uvec2 sum = uvec2(0u);
    for (uint j = 0u; j < kPerThread; ++j) {
        uint idx = first + j;
        v[j] = idx < uBrickCount ? places[idx] : uvec2(0u);
        sum += v[j];
    }
    uvec2 total = groupScan(sum);
    if (uPhase == 0) {
        if (lid == 0u) blockSums[group] = total;
        return;
    }
    uvec2 place = blockSums[group] + partial[lid];
    for (uint j = 0u; j < kPerThread; ++j) {
        uint idx = first + j;
        if (idx >= uBrickCount) break;
        places[idx] = place;
        place += v[j];
    }
}
