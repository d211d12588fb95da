// Buffer layouts and constants that the shaders share with the C++ side
// (src/gpu/gpu_layout.h, src/core/sampling.h).

// Fixed-point scale of volume fractions (src/core/sampling.h: kFixedScale).
const float kFixedScale = 16777216.0;
const int kBrickVoxels = 512;
// Smallest share of a voxel a sample gives it (src/core/sampling.h: kMinVoxelShare).
const float kMinVoxelShare = 1.0 / 65536.0;

// One curve segment (96 bytes): control points in voxel units relative to
// the segment's anchor, an integer voxel (p[1].w, p[2].w, p[3].w), so that
// floats keep their precision anywhere in the grid; p[0].w = twist rate
// (radians per voxel unit of length);
// up.w = twist phase at the segment's start; info = first slice within the
// draw's list, slice count, float bits of the segment length, yarn.
struct GpuSegment {
    vec4 p[4];
    vec4 up;
    uvec4 info;
};

// One voxel fragment (16 bytes): region-local key (brick << 9 | voxel in
// brick), fixed-point volume fraction, axis code, float bits of the density.
struct Fragment {
    uint key;
    uint weight;
    uint axis;
    uint density;
};

// One slice placed from its segment (slice_setup.comp), 96 bytes: what the
// sprite's vertex shader and the sampling pass read of it.
struct SliceRecord {
    vec4 center;    // xyz: voxel units from `anchor`; w: projection axis (int bits)
    ivec4 anchor;   // xyz: the integer voxel the slice's coordinates are relative to
    vec4 right;     // xyz: the cross-section's right; w: thickness, voxel units
    vec4 up;        // xyz: the cross-section's up (tangent x right); w: radians it turns by at the next slice
    vec4 tangent;   // xyz; w: slab depth along the projection axis before the bend's scale, voxel units
    vec4 curvature; // xyz: curvature vector, 1 / voxel units; w: unused
};

// Slices one point sprite draws at most (SLICE_POINTS: a run of consecutive
// slices, slice_runs.comp; SLICE_RUN, chooseSlicePrimitive in
// src/gpu/gl_voxelizer.cpp: 1, or gpu_layout.h's kSliceRunMax where the yarn
// is thin on the face); a triangle draws one.
#if SLICE_POINTS
const int kRunSlices = SLICE_RUN;
#else
const int kRunSlices = 1;
#endif
