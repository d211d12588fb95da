// The GPU radix sort (src/gpu/radix_sort.h), step 1 of a pass over one
// 8-bit digit: each tile of kTile pairs counts its keys' digits. The counts
// are stored digit by digit (digit * uTiles + tile), so that one exclusive
// scan of them (radix_scan.comp) gives every tile the place in the output
// where its pairs of each digit start. The first pass leaves out the pairs
// whose value is kDropped; later passes sort the `kept` pairs it wrote.
layout(local_size_x = 256) in;

layout(std430, binding = kSortKeysInBinding) readonly buffer KeysIn { uint keysIn[]; };
layout(std430, binding = kSortValuesInBinding) readonly buffer ValuesIn { uint valuesIn[]; };
layout(std430, binding = kSortHistogramBinding) writeonly buffer Histogram { uint histogram[]; };
layout(std430, binding = kSortKeptBinding) readonly buffer Kept { uint kept; };

uniform uint uCount;    // the first pass: the pairs in the input
uniform int uFirstPass; // 1: uCount pairs, some dropped; 0: the `kept` pairs
uniform uint uShift;    // the digit's lowest bit
uniform uint uTiles;

const uint kDropped = 0xffffffffu;
const uint kPerThread = RADIX_PER_THREAD;
const uint kTile = 256u * kPerThread;
shared uint bins[256];

void main() {
    uint lid = gl_LocalInvocationID.x;
    uint count = uFirstPass != 0 ? uCount : kept;
    for (uint tile = gl_WorkGroupID.x; tile < uTiles; tile += gl_NumWorkGroups.x) {
        bins[lid] = 0u;
        barrier();
        uint first = tile * kTile;
        for (uint j = 0u; j < kPerThread; ++j) {
            uint i = first + j * 256u + lid;
            if (i < count && (uFirstPass == 0 || valuesIn[i] != kDropped))
                atomicAdd(bins[(keysIn[i] >> uShift) & 255u], 1u);
        }
        barrier();
        histogram[lid * uTiles + tile] = bins[lid];
        barrier(); // the counts are read before the next tile clears them
    }
}
