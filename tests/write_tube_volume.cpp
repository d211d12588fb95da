// Writes straight yarn-like tubes along z, the same garment at any
// resolution: `write_tube_volume OUT.vdb RESOLUTION LOD_LEVELS` writes a .vdb,
// `write_tube_volume OUT.work RESOLUTION work` a work directory of 16 regions
// (z slabs). 8 x 8 tubes, each of radius 6/1024 of the grid, density 1
// inside, the axis +z. The inspect memory test (inspect_memory.py) writes
// both at two resolutions; bricks go out a z slab at a time, so the writer
// holds one slab (or one region).
#include "core/bricks.h"
#include "core/run_metadata.h"
#include "store/brick_store.h"
#include "vdb/vdb_writer.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

using namespace yv;

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: write_tube_volume OUT.vdb RESOLUTION LOD_LEVELS | OUT.work RESOLUTION work\n");
        return 2;
    }
    try {
        const int resolution = std::atoi(argv[2]);
        VoxelGrid grid;
        grid.voxelSize = 1.0 / resolution;
        grid.dims = glm::ivec3(resolution);
        const double radius = 6.0 * resolution / 1024.0, spacing = resolution / 8.0;
        const int bricks = resolution / kBrickSize;
        const auto slab = [&](int bz) {
            std::vector<VoxelBrick> out;
            for (int tx = 0; tx < 8; ++tx)
                for (int ty = 0; ty < 8; ++ty) {
                    const double cx = (tx + 0.5) * spacing, cy = (ty + 0.5) * spacing;
                    for (int bx = int((cx - radius) / 8); bx <= int((cx + radius) / 8); ++bx)
                        for (int by = int((cy - radius) / 8); by <= int((cy + radius) / 8); ++by) {
                            VoxelBrick b;
                            b.key = brickKey({bx, by, bz});
                            for (int x = 0; x < 8; ++x)
                                for (int y = 0; y < 8; ++y) {
                                    const double dx = bx * 8 + x + 0.5 - cx, dy = by * 8 + y + 0.5 - cy;
                                    if (dx * dx + dy * dy > radius * radius) continue;
                                    for (int z = 0; z < 8; ++z) {
                                        const int v = brickOffset(x, y, z);
                                        b.activeMask[v >> 6] |= std::uint64_t(1) << (v & 63);
                                        b.density[v] = 1.0f;
                                        b.orientation[v] = glm::vec3(0, 0, 1);
                                    }
                                }
                            if (b.activeCount()) out.push_back(b);
                        }
                }
            return out;
        };
        if (std::string(argv[3]) == "work") {
            StoreManifest manifest;
            manifest.fingerprint = 0x7b5e;
            manifest.grid = grid;
            BrickStore store(argv[1], manifest, false);
            constexpr int kRegions = 16;
            const int slabsPerRegion = bricks / kRegions;
            for (int r = 0; r < kRegions; ++r) {
                std::vector<VoxelBrick> region;
                for (int bz = r * slabsPerRegion; bz < (r + 1) * slabsPerRegion; ++bz) {
                    std::vector<VoxelBrick> one = slab(bz);
                    region.insert(region.end(), one.begin(), one.end());
                }
                store.writeRegion(std::uint64_t(r), {0, 0, r * slabsPerRegion * kBrickSize},
                                  {resolution, resolution, (r + 1) * slabsPerRegion * kBrickSize}, std::move(region));
            }
            store.markComplete(kRegions);
            return 0;
        }
        VdbWriteOptions options;
        options.lodLevels = std::atoi(argv[3]);
        VdbAssembler writer(argv[1], grid, Reduce::Mean, options);
        for (int bz = 0; bz < bricks; ++bz) writer.add(slab(bz), "slab " + std::to_string(bz));
        writer.write(VolumeMetadata{});
    } catch (const std::exception& e) {
        std::fprintf(stderr, "write_tube_volume: %s\n", e.what());
        return 1;
    }
    return 0;
}
