// libFuzzer target: the region-file reader (src/store/region_file.cpp), the
// way BrickStore reads a region: header, identity, then the whole body.
#include "core/error.h"
#include "store/region_file.h"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const yv::RegionHeader h = yv::parseRegionHeader(data, size, "fuzz/region-0.yvb");
        // The run the header claims, so that identity passes and the body is read.
        yv::StoreManifest run;
        run.fingerprint = h.fingerprint;
        run.grid = h.grid;
        run.reduce = h.reduce;
        yv::checkRegionIdentity(h, run, h.id, &h.min, &h.max, "fuzz/region-0.yvb");
        std::vector<yv::VoxelBrick> bricks;
        yv::decodeRegionBody(data, h, "fuzz/region-0.yvb", &bricks);
    } catch (const yv::Error&) {
    }
    return 0;
}
