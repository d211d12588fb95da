// The GPU radix sort (src/gpu/radix_sort.h), step 3 of a pass: each tile
// sorts its pairs by the digit in shared memory, stably, and writes each
// pair to the place the scanned histogram gives its tile for that digit,
// plus its rank among the tile's pairs of the same digit. Stable within the
// tile and tiles in order, so the pass is stable: after the passes over
// every digit, pairs of equal keys keep the order of the first pass's input.
//
// The tile sorts itself by one bit at a time (a split: the pairs whose bit
// is 0, in order, then those whose bit is 1, in order), each split one
// prefix sum across the work group. In the first pass a ninth split puts
// the dropped pairs (value kDropped, and the places past the input's end)
// after the kept ones, which are the only ones written.
layout(local_size_x = 256) in;

layout(std430, binding = kSortKeysInBinding) readonly buffer KeysIn { uint keysIn[]; };
layout(std430, binding = kSortValuesInBinding) readonly buffer ValuesIn { uint valuesIn[]; };
layout(std430, binding = kSortKeysOutBinding) writeonly buffer KeysOut { uint keysOut[]; };
layout(std430, binding = kSortValuesOutBinding) writeonly buffer ValuesOut { uint valuesOut[]; };
layout(std430, binding = kSortHistogramBinding) readonly buffer Histogram { uint histogram[]; };
layout(std430, binding = kSortKeptBinding) readonly buffer Kept { uint kept; };

uniform uint uCount;    // the first pass: the pairs in the input
uniform int uFirstPass; // 1: uCount pairs, some dropped; 0: the `kept` pairs
uniform uint uShift;    // the digit's lowest bit
uniform uint uTiles;
uniform int uWriteKeys; // 0: the last pass writes only the values

const uint kDropped = 0xffffffffu;
const uint kPerThread = RADIX_PER_THREAD;
const uint kTile = 256u * kPerThread;
shared uint tileKeys[kTile], tileValues[kTile];
shared uint partial[256], rowSums[16], groupTotal;
shared uint digitStart[256]; // per digit: its pairs in the tile, then where they start in the sorted tile
shared bool oneDigit;        // the tile's kept pairs all have one digit (already in order by it)

// The sum of `value` over the threads before this one; `total` over all of
// them. Three barriers (16 rows of 16 summed in turn, then the rows), where
// a Hillis-Steele scan takes 16: a tile's sort runs 8 or 9 of these.
uint groupScan(uint value, out uint total) {
    uint lid = gl_LocalInvocationID.x;
    partial[lid] = value;
    barrier();
    if (lid < 16u) {
        uint sum = 0u;
        for (uint k = 0u; k < 16u; ++k) {
            uint v = partial[16u * lid + k];
            partial[16u * lid + k] = sum;
            sum += v;
        }
        rowSums[lid] = sum;
    }
    barrier();
    if (lid == 0u) {
        uint sum = 0u;
        for (uint k = 0u; k < 16u; ++k) {
            uint v = rowSums[k];
            rowSums[k] = sum;
            sum += v;
        }
        groupTotal = sum;
    }
    barrier();
    // (What is read here is written again only after the next call's first barrier.)
    total = groupTotal;
    return partial[lid] + rowSums[lid >> 4];
}

// The bit a split sorts by: bits 0 to 7 of the digit, then 8: dropped.
uint splitBit(uint key, uint value, uint bit) {
    return bit < 8u ? (key >> (uShift + bit)) & 1u : uint(value == kDropped);
}

void main() {
    uint lid = gl_LocalInvocationID.x;
    uint count = uFirstPass != 0 ? uCount : kept;
    for (uint tile = gl_WorkGroupID.x; tile < uTiles; tile += gl_NumWorkGroups.x) {
        uint first = tile * kTile;
        digitStart[lid] = 0u;
        if (lid == 0u) oneDigit = false;
        barrier();
        // The tile, read coalesced; a place past the end is a dropped pair.
        for (uint j = 0u; j < kPerThread; ++j) {
            uint q = j * 256u + lid, i = first + q;
            uint key = 0u, value = kDropped;
            if (i < count) {
                key = keysIn[i];
                value = valuesIn[i];
            }
            tileKeys[q] = key;
            tileValues[q] = value;
            if (value != kDropped) atomicAdd(digitStart[(key >> uShift) & 255u], 1u);
        }
        barrier();
        uint keptInTile;
        uint count = digitStart[lid];
        uint start = groupScan(count, keptInTile); // (each thread reads and writes its own digit)
        digitStart[lid] = start;
        if (count == keptInTile && count != 0u) oneDigit = true;
        barrier();
        if (keptInTile == 0u) continue; // the same for the whole work group

        // This thread's pairs: kPerThread consecutive places of the tile.
        uint keys[kPerThread], values[kPerThread];
        for (uint j = 0u; j < kPerThread; ++j) {
            keys[j] = tileKeys[lid * kPerThread + j];
            values[j] = tileValues[lid * kPerThread + j];
        }
        // A tile whose pairs share the digit (often so for the distances'
        // exponent bits) needs at most the split of the dropped ones.
        uint splits = keptInTile < kTile ? 9u : 8u;
        for (uint bit = oneDigit ? 8u : 0u; bit < splits; ++bit) {
            uint ones = 0u;
            for (uint j = 0u; j < kPerThread; ++j) ones += splitBit(keys[j], values[j], bit);
            uint allOnes;
            uint onesBefore = groupScan(ones, allOnes);
            uint zero = lid * kPerThread - onesBefore, one = kTile - allOnes + onesBefore;
            // (groupScan's barriers: every thread has read its pairs before they move.)
            for (uint j = 0u; j < kPerThread; ++j) {
                uint at = splitBit(keys[j], values[j], bit) != 0u ? one++ : zero++;
                tileKeys[at] = keys[j];
                tileValues[at] = values[j];
            }
            barrier();
            for (uint j = 0u; j < kPerThread; ++j) {
                keys[j] = tileKeys[lid * kPerThread + j];
                values[j] = tileValues[lid * kPerThread + j];
            }
        }

        // Written coalesced from the sorted tile: its kept pairs come first.
        for (uint j = 0u; j < kPerThread; ++j) {
            uint q = j * 256u + lid;
            if (q >= keptInTile) break;
            uint key = tileKeys[q];
            uint digit = (key >> uShift) & 255u;
            uint at = histogram[digit * uTiles + tile] + q - digitStart[digit];
            if (uWriteKeys != 0) keysOut[at] = key;
            valuesOut[at] = tileValues[q];
        }
        barrier(); // the tile is read before the next one is loaded
    }
}
