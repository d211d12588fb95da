// libFuzzer target: yarnvox's own .vdb reader (src/vdb/vdb_index.cpp,
// src/vdb/leaf_records.cpp) the way inspect reads a file: header and grids,
// then each grid's topology and every leaf's record; and the grids'
// checksums as --verify and export check them (src/vdb/grid_checksums.cpp). The reader works on a
// file, so the input goes into an in-memory one (memfd).
#include "core/error.h"
#include "vdb/grid_checksums.h"
#include "vdb/leaf_records.h"
#include "vdb/vdb_index.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const int fd = ::memfd_create("fuzz.vdb", MFD_CLOEXEC);
    if (fd < 0) return 0;
    if (size > 0 && ::write(fd, data, size) != static_cast<ssize_t>(size)) {
        ::close(fd);
        return 0;
    }
    try {
        const yv::VdbIndex index("/proc/self/fd/" + std::to_string(fd));
        for (const yv::StoredMetadata& m : index.fileMetadata()) (void)m.text();
        try {
            (void)yv::verifyGridChecksums(index);
        } catch (const yv::Error&) {
        }
        if (index.inSubset()) {
            std::vector<float> values(512 * 3);
            std::vector<std::uint8_t> bytes;
            for (const yv::VdbGridInfo& grid : index.grids()) {
                const yv::VdbLeafTable table = index.leaves(grid);
                for (std::size_t leaf = 0; leaf + 1 < table.records.size(); ++leaf) {
                    yv::readLeafRecords(index, grid, table, leaf, leaf + 1, bytes);
                    yv::decodeLeafRecord(bytes, index, grid, leaf, table.bricks[leaf], table.records[leaf], values.data());
                }
            }
        }
    } catch (const yv::Error&) {
    }
    ::close(fd);
    return 0;
}
