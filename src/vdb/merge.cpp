#include "vdb/merge.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "vdb/tree_order.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <thread>

namespace yv {
namespace {

/// Calls `fn(index, bricks)` for each region, reading and verifying a few
/// regions at once: enough to keep the cores busy while one region waits on
/// the disk, few enough that memory stays a few regions' worth.
void forEachRegion(const BrickStore& store, const std::vector<RegionInfo>& regions,
                   const std::function<void(std::size_t, std::vector<VoxelBrick>&)>& fn) {
    const std::size_t tokens = std::clamp<std::size_t>(std::thread::hardware_concurrency() / 4, 2, 4);
    std::size_t next = 0;
    tbb::parallel_pipeline(
        tokens,
        tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                            [&](tbb::flow_control& fc) -> std::size_t {
                                                if (next == regions.size()) {
                                                    fc.stop();
                                                    return 0;
                                                }
                                                return next++;
                                            }) &
            tbb::make_filter<std::size_t, void>(tbb::filter_mode::parallel, [&](std::size_t i) {
                // A signal stops the merge at its next region.
                throwIfInterrupted("while reading the regions of " + store.dir());
                std::vector<VoxelBrick> bricks = store.readRegion(regions[i].id);
                fn(i, bricks);
                signalAtTestPoint("merge-region");
            }));
}

std::string regionLabel(const BrickStore& store, std::uint64_t id) { return store.regionPath(id); }

} // namespace

void mergeStoreToVdb(const BrickStore& store, const std::string& outPath, const VolumeMetadata& metadata,
                     const VdbWriteOptions& options) {
    const StoreManifest& m = store.manifest();
    if (!m.completeRegions)
        throw Error(store.dir() + ": the run that fills this work dir has not finished: run it again with "
                                  "--resume before merging");
    const std::vector<RegionInfo> regions = store.listRegions();
    if (regions.size() != *m.completeRegions)
        throw Error(store.dir() + ": the finished run wrote " + std::to_string(*m.completeRegions) +
                    " regions, but " + std::to_string(regions.size()) +
                    " region files are on disk: run it again with --resume");
    const auto start = std::chrono::steady_clock::now();
    VdbAssembler assembler(outPath, m.grid, m.reduce, options);
    // In the tree order of their lowest corners, so the leaves stream into
    // the file while later regions are read, as a run without a work dir
    // streams them: the two give the same file.
    std::vector<RegionInfo> inTreeOrder = regions;
    std::vector<std::uint64_t> firstOrders = sortByFirstTreeOrder(inTreeOrder);
    if (options.streamLeaves) assembler.streamRegions(std::move(firstOrders));
    forEachRegion(store, inTreeOrder, [&](std::size_t i, std::vector<VoxelBrick>& bricks) {
        assembler.add(bricks, regionLabel(store, inTreeOrder[i].id));
        assembler.regionDone(i);
    });
    if (options.timings)
        options.timings->readSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    VolumeMetadata withRegions = metadata;
    withRegions.regions = recordedRegions(regions);
    assembler.write(withRegions);
}

std::vector<RecordedRegion> recordedRegions(const std::vector<RegionInfo>& regions) {
    std::vector<RecordedRegion> out;
    out.reserve(regions.size());
    for (const RegionInfo& r : regions) out.push_back(RecordedRegion{r.id, r.min, r.max, r.activeVoxels});
    return out;
}

void mergeStoreToVdb(const std::string& dir, const std::string& outPath, const VolumeMetadata& metadata,
                     const VdbWriteOptions& options) {
    const BrickStore store(dir);
    mergeStoreToVdb(store, outPath, metadata, options);
}

BrickVolume loadStore(const std::string& dir) {
    const BrickStore store(dir);
    const std::vector<RegionInfo> regions = store.listRegions();
    std::vector<std::vector<VoxelBrick>> parts(regions.size());
    forEachRegion(store, regions,
                  [&](std::size_t i, std::vector<VoxelBrick>& bricks) { parts[i] = std::move(bricks); });

    // Each region is sorted already; a sort of (key, region, index) places
    // them together without moving 8 KB bricks around.
    struct Slot {
        std::uint64_t key;
        std::uint32_t part, index;
    };
    std::vector<Slot> slots;
    for (std::size_t p = 0; p < parts.size(); ++p)
        for (std::size_t i = 0; i < parts[p].size(); ++i)
            slots.push_back({parts[p][i].key, std::uint32_t(p), std::uint32_t(i)});
    tbb::parallel_sort(slots.begin(), slots.end(), [](const Slot& a, const Slot& b) { return a.key < b.key; });

    BrickVolume volume;
    volume.grid = store.manifest().grid;
    volume.reduce = store.manifest().reduce;
    volume.bricks.reserve(slots.size());
    for (std::size_t s = 0; s < slots.size(); ++s) {
        if (s > 0 && slots[s].key == slots[s - 1].key)
            throw Error(dir + ": brick at voxel (" + std::to_string(brickCoord(slots[s].key).x * 8) + ", " +
                        std::to_string(brickCoord(slots[s].key).y * 8) + ", " +
                        std::to_string(brickCoord(slots[s].key).z * 8) + ") is held by both " +
                        regionLabel(store, regions[slots[s - 1].part].id) + " and " +
                        regionLabel(store, regions[slots[s].part].id));
        volume.bricks.push_back(parts[slots[s].part][slots[s].index]);
    }
    return volume;
}

} // namespace yv
