// Brick pass 2: exclusive prefix sum of the brick flags, in place, giving each
// touched brick its slot in the brick buffer. Three phases (uPhase):
//   0: each work group sums its 1024 flags into blockSums
//   1: one work group scans blockSums and writes the total to counts[0]
//   2: each work group rescans its flags, adds its block offset, and writes
//      slots (in place of the flags) and the inverse map slot -> brick.
layout(local_size_x = 256) in;

layout(std430, binding = kBrickSlotsBinding) buffer Flags { uint flags[]; };
layout(std430, binding = kBrickBlockSumsBinding) buffer BlockSums { uint blockSums[]; };
layout(std430, binding = kBrickCountsBinding) buffer Counts { uint counts[]; };
layout(std430, binding = kSlotBricksBinding) writeonly buffer SlotBricks { uint slotBrick[]; };

uniform uint uBrickCount;
uniform uint uBlockCount;
uniform int uPhase;

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
            uint v[4];
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
        if (lid == 0u) counts[0] = carry;
        return;
    }

    uint group = gl_WorkGroupID.x;
    uint first = group * kPerGroup + lid * kPerThread;
    uint v[4];
    uint sum = 0u;
    for (uint j = 0u; j < kPerThread; ++j) {
        uint idx = first + j;
        v[j] = idx < uBrickCount ? flags[idx] : 0u;
        sum += v[j];
    }
    uint total = groupScan(sum);
    if (uPhase == 0) {
        if (lid == 0u) blockSums[group] = total;
        return;
    }
    uint slot = blockSums[group] + partial[lid];
    for (uint j = 0u; j < kPerThread; ++j) {
        uint idx = first + j;
        if (idx >= uBrickCount) break;
        flags[idx] = slot; // now the brick's slot (meaningful only where it was flagged)
        if (v[j] != 0u) slotBrick[slot] = idx;
        slot += v[j];
    }
}
