// The binding points of every shader storage block, atomic counter, texture
// and image that a yarnvox shader declares: one name a buffer (or texture),
// stated once for both languages. GlProgram puts this file before every
// shader it compiles (ahead of the shader and its includes), and src/gpu/gl_bindings.h
// includes it into namespace yv, so a shader's `layout(binding = kItems)` and
// the C++ that binds the buffer there say the same name. Only `const int`
// lines and comments: valid GLSL 4.50 (a constant expression may name a
// binding) and valid C++.
//
// A number serves several names: each pass binds every buffer it reads
// before it runs, so a name's number only has to differ from those of the
// other buffers of the same program. (Storage bindings stay below 8, the
// least GL 4.5 guarantees a compute shader.)

// --- The slices: placed (slice_setup.comp), joined into runs
// (slice_runs.comp), drawn (slice.vert), sampled (sample.comp).
const int kSegmentsBinding = 0;   // GpuSegment per segment of the garment
const int kDrawListBinding = 1;   // per segment of the draw: its index and its first instance
const int kRunDrawBinding = 3;    // point sprites: the runs' glDrawArraysIndirect command
const int kRunsBinding = 4;       // point sprites: a run's first slice and its slices
const int kSlicesBinding = 5;     // SliceRecord per instance of the draw

// --- The lists the raster and the sampling append to (append.frag, sample.comp).
const int kFragmentsBinding = 2;        // Fragment per voxel a sample reaches
const int kFragmentCounterBinding = 3;  // the fragment count's word, then its wrap flag
const int kAlbedoFragmentsBinding = 4;  // --albedo: each fragment's colour, at its own slot
const int kItemsBinding = 6;            // sample item per slice and pixel that can hold fibre
const int kItemCounterBinding = 7;      // the item count's word, its wrap flag, then the sampling's dispatch size
// Atomic counter buffers (their own binding points): the item counter (the
// raster) and the fragment counter (the sampling).
const int kItemCountAtomic = 0;
const int kFragmentCountAtomic = 0;

// --- Textures and images of the sampling (sample.comp, dense.frag).
const int kCrossSectionUnit = 0;  // the cross-section's density (cross_section_texture.h)
const int kAlbedoUnit = 1;        // --albedo: the fibres' colour times density
const int kDenseDensityImage = 0; // the dense method's three 3D textures
const int kDenseThetaImage = 1;
const int kDensePhiImage = 2;

// --- The brick passes: flag, scan, scatter, max-orient (brick_*.comp).
const int kClearedWordsBinding = 0;     // the words buffer_clear.comp zeroes
const int kBrickSlotsBinding = 3;       // per region brick: its flag, which the scan turns into its slot
const int kBrickBlockSumsBinding = 4;   // the scan's sum per block of 1024 bricks
const int kBrickCountsBinding = 5;      // the scan's result: the touched bricks' count
const int kSlotBricksBinding = 6;       // per slot: its region brick index
const int kBrickWordsBinding = 7;       // wordsPerVoxel channels of 512 words per slot (also the resolve's input)

// --- The resolve (brick_resolve.comp, brick_resolve_scan.comp).
const int kResolvePlacesBinding = 1;     // per slot: its place among the kept bricks and voxels
const int kResolveKeysBinding = 2;       // per slot: its region brick index, or two words of its key
const int kPackedHeadersBinding = 3;     // the packed output: its headers,
const int kPackedVoxelsBinding = 4;      // its voxels (the same buffer, from uVoxelBase)
const int kPackedAlbedoBinding = 5;      // and with --albedo their colours (from uAlbedoBase)
const int kResolveBlockSumsBinding = 5;  // the resolve scan's sums per block of 1024 slots
const int kResolveTotalsBinding = 6;     // kept bricks and active voxels

// --- yarnvox inspect's renders (inspect_*.vert, .geom, .frag).
const int kEntryExitUnit = 0;         // each pixel's ray entry and exit (the proxy's render)
const int kIndirectionUnit = 1;       // level brick -> atlas slot + 1 (0: empty)
const int kDensityAtlasUnit = 2;      // the bricks' density, packed
const int kOrientationAtlasUnit = 3;  // the bricks' orientation, packed
const int kTransferFunctionUnit = 4;  // density -> colour and opacity
const int kLightBufferUnit = 5;       // the slicing renderer's light buffer
const int kSliceTableUnit = 0;        // the slices drawn: (centre, thickness), (tangent, place in its run)
const int kSliceSpansUnit = 1;        // per slice drawn: the slices of its run its slab stands for
const int kBrickOrderBinding = 0;     // the splats' bricks, back to front

// --- The GPU radix sort (radix_*.comp, gpu/radix_sort.h) and the slices'
// keys it sorts (inspect_slice_keys.comp).
const int kSortKeysInBinding = 0;     // the pairs a pass reads: keys,
const int kSortValuesInBinding = 1;   // and values (kDropped: left out)
const int kSortKeysOutBinding = 2;    // the pairs a pass writes
const int kSortValuesOutBinding = 3;
const int kSortHistogramBinding = 4;  // per digit and tile: its pairs, then (scanned) where they go
const int kSortBlockSumsBinding = 5;  // the histogram scan's sum per block of 1024 counts
const int kSortKeptBinding = 6;       // the pairs kept (not dropped) by the first pass
const int kSliceSpansBinding = 2;     // inspect_slices_keys.comp writes kSliceSpansUnit's buffer
const int kSliceLargestBinding = 3;   // and the most pixels a slab kept may cover, across (slice_renderer.cpp)
const int kSliceDrawsBinding = 4;     // inspect_slices_choose.comp writes the draws' instance counts

// --- The slices composited by tiles of the picture (render/slice_tiles.h):
// inspect_slices_tiles.comp counts each slab's tiles (reading the keys
// pass's pairs at kSortKeysInBinding and kSortValuesInBinding), emits a
// (tile, depth) pair for each, and finds each tile's run of the sorted
// pairs; inspect_slices_composite.comp blends them.
const int kSliceTileKeysBinding = 2;    // per pair: tile and depth, then (sorted) the same in order
const int kSliceTileValuesBinding = 3;  // per pair: its slice
const int kSliceTileCountsBinding = 4;  // per slice: its tiles, then (scanned) its first pair
const int kSliceTileTotalsBinding = 5;  // the pairs, the slabs kept, and whether one spans too many tiles
const int kSliceTileRangesBinding = 6;  // per tile: its first pair and one past its last
const int kSliceTileEntriesBinding = 7; // the pairs' slices in (tile, depth) order
const int kSliceTileRectsBinding = 7;   // per slice: its tiles, a byte each of x0, y0, x1, y1 (the count writes, the pairs read)
const int kSliceTilesImageUnit = 0;     // the composited picture (image unit), written
const int kSliceTilesPictureUnit = 2;   // and read by inspect_slices_composite.frag (texture unit)
