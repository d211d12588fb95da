#include "inspect/inspect_store.h"

#include "core/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

namespace yv {
namespace {

/// Regions read at once by a verify.
constexpr std::size_t kRegionsInFlight = 8;

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
    // Then the voxels, a few regions at a time (each is decoded in parallel
    // chunks, and its statistics gathered in parallel): with every region in
    // flight at once, an 8192 work dir held 3 GB of decoded bricks.
    for (std::size_t first = 0; verify && first < ids.size(); first += kRegionsInFlight) {
        const std::size_t last = std::min(ids.size(), first + kRegionsInFlight);
        tbb::parallel_for(first, last, [&](std::size_t i) {
            if (!s.regions[i].problem.empty()) return;
            try {
                const std::vector<VoxelBrick> bricks = store.readRegion(ids[i]);
                perRegion[i] = tbb::parallel_reduce(
                    tbb::blocked_range<std::size_t>(0, bricks.size(), 256), VoxelStatistics{},
                    [&](const tbb::blocked_range<std::size_t>& r, VoxelStatistics acc) {
                        for (std::size_t b = r.begin(); b != r.end(); ++b)
                            for (int v = 0; v < kBrickVoxels; ++v)
                                if (bricks[b].isActive(v)) acc.add(bricks[b].density[v], bricks[b].orientation[v]);
                        return acc;
                    },
                    [](VoxelStatistics a, const VoxelStatistics& b) { return a += b; });
            } catch (const Error& e) {
                s.regions[i].problem = e.what();
            }
        });
    }
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
