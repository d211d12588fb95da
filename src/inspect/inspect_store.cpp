#include "inspect/inspect_store.h"

#include "core/error.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace yv {
namespace {

void addChunk(const RawBricks& bricks, VoxelStatistics& stats) {
    for (std::size_t b = 0; b < bricks.count; ++b)
        stats.addBrick(bricks.density(b), bricks.orientation(b), bricks.activeMask(b));
}

} // namespace

StoreSummary inspectStore(const std::string& dir, bool verify) {
    const BrickStore store(dir);
    StoreSummary s;
    s.dir = dir;
    s.manifest = store.manifest();
    s.verified = verify;
    const std::vector<std::uint64_t> ids = store.regionIds();
    s.regions.resize(ids.size());
    std::vector<VoxelStatistics> perRegion(verify ? ids.size() : 0);
    // Headers first, all regions side by side: they are small.
    tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t i) {
        RegionRow& row = s.regions[i];
        row.info.id = ids[i];
        try {
            row.info = store.regionInfo(ids[i]);
            row.valueBytes = row.info.activeVoxels * 16;
        } catch (const Error& e) {
            row.problem = e.what();
        }
    });
    // Then the voxels: every region and every chunk of it side by side, each
    // chunk decoded into its thread's buffers and counted in place, so memory
    // stays at a few chunks a thread whatever the volume's size.
    if (verify)
        tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t i) {
            if (!s.regions[i].problem.empty()) return;
            tbb::combinable<VoxelStatistics> stats;
            try {
                store.forEachChunk(ids[i], [&](const RawBricks& bricks) { addChunk(bricks, stats.local()); });
                perRegion[i] = stats.combine([](VoxelStatistics a, const VoxelStatistics& b) { return a += b; });
            } catch (const Error& e) {
                s.regions[i].problem = e.what();
            }
        });
    for (std::size_t i = 0; i < s.regions.size(); ++i) {
        const RegionRow& row = s.regions[i];
        if (!row.problem.empty()) {
            ++s.badRegions;
            continue;
        }
        s.bricks += row.info.brickCount;
        s.activeVoxels += row.info.activeVoxels;
        s.bytesOnDisk += row.info.bytesOnDisk;
        s.valueBytes += row.valueBytes;
        if (verify) s.voxels += perRegion[i];
    }
    return s;
}

} // namespace yv
