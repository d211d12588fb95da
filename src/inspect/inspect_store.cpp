#include "inspect/inspect_store.h"

#include "core/error.h"

#include <tbb/parallel_for.h>

namespace yv {

StoreSummary inspectStore(const std::string& dir, bool verify) {
    const BrickStore store(dir);
    StoreSummary s;
    s.dir = dir;
    s.manifest = store.manifest();
    s.verified = verify;
    const std::vector<std::uint64_t> ids = store.regionIds();
    s.regions.resize(ids.size());
    std::vector<VoxelStatistics> perRegion(verify ? ids.size() : 0);
    // Regions are independent: read (and, verifying, decompress) them in parallel.
    tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t i) {
        RegionRow& row = s.regions[i];
        row.info.id = ids[i];
        try {
            row.info = store.regionInfo(ids[i]);
            row.valueBytes = row.info.activeVoxels * 16;
            if (verify)
                for (const VoxelBrick& b : store.readRegion(ids[i]))
                    for (int v = 0; v < kBrickVoxels; ++v)
                        if (b.isActive(v)) perRegion[i].add(b.density[v], b.orientation[v]);
        } catch (const Error& e) {
            row.problem = e.what();
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
