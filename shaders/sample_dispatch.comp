// Sizes the sampling pass from the raster's item count on the GPU
// (glDispatchComputeIndirect), so the host never waits between the two.
layout(local_size_x = 1) in;
layout(std430, binding = kItemCounterBinding) buffer ItemCounter {
    uint itemCount;
    uint itemWrapped;
    uint unused[2];
    uvec4 groups; // x, y, z: the dispatch's work groups
};
uniform uint uItemCapacity;
uniform uint uGroupSize;  // sample.comp's local_size_x
uniform uint uMaxGroups;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]; sample.comp loops over the rest
void main() {
    uint items = min(itemCount, uItemCapacity);
    groups = uvec4(min((items + uGroupSize - 1u) / uGroupSize, uMaxGroups), 1u, 1u, 0u);
}
