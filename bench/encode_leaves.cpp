// What the .vdb writer's threads spend a voxel on: synthetic resolved bricks
// (PackedBricks, as a GPU pass hands them over) added to a VdbAssembler in
// region-sized batches on K threads, as a run's writers do, and the file
// written. At 8192 those threads encode over a billion voxels while the GPU
// thread copies the next pass and the leaf stream writes: every nanosecond a
// voxel costs here is a second of a core there.
//
//   yv_bench_encode_leaves [--bricks 200000] [--fill 0.4] [--threads 8]
//                          [--batch 8192] [--precision half|float] [--lod preview|0]
//                          [--rounds 3] [--out DIR]
// Prints one JSON line a round: seconds to add every batch (encode), to
// write the file, and nanoseconds an active voxel of each.
#include "core/error.h"
#include "core/packed_bricks.h"
#include "core/run_metadata.h"
#include "core/voxel_grid.h"
#include "vdb/lod_request.h"
#include "vdb/vdb_writer.h"

#include <glm/geometric.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace yv;

namespace {

double since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Bricks along a diagonal band of the grid, each with about `fill` of its
/// voxels active: densities in (0, 1], a few above, unit axes.
std::vector<PackedBricks> makeBatches(std::size_t bricks, double fill, std::size_t perBatch, int bricksPerAxis) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), axis(-1.0f, 1.0f);
    std::vector<PackedBricks> batches;
    for (std::size_t first = 0; first < bricks; first += perBatch) {
        PackedBricks& batch = batches.emplace_back();
        const std::size_t count = std::min(perBatch, bricks - first);
        std::vector<PackedBrickHeader> headers(count);
        std::vector<PackedVoxel> voxels;
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t b = first + i;
            const glm::ivec3 c(int(b % std::size_t(bricksPerAxis)), int(b / std::size_t(bricksPerAxis) % std::size_t(bricksPerAxis)),
                               int(b / std::size_t(bricksPerAxis) / std::size_t(bricksPerAxis)));
            PackedBrickHeader& h = headers[i];
            h = {};
            const std::uint64_t key = brickKey(c);
            h.key[0] = std::uint32_t(key);
            h.key[1] = std::uint32_t(key >> 32);
            h.firstVoxel = std::uint32_t(voxels.size());
            for (int v = 0; v < kBrickVoxels; ++v) {
                if (unit(random) >= fill && !(v == 0 && h.activeCount == 0)) continue;
                h.activeMask[v / 32] |= 1u << (v % 32);
                ++h.activeCount;
                glm::vec3 a(axis(random), axis(random), axis(random));
                a = glm::length(a) > 1e-3f ? glm::normalize(a) : glm::vec3(1, 0, 0);
                voxels.push_back({unit(random) * 1.02f, {a.x, a.y, a.z}});
            }
        }
        batch.append(headers.data(), headers.size(), voxels.data(), voxels.size(), nullptr);
    }
    return batches;
}

} // namespace

int main(int argc, char** argv) try {
    std::size_t bricks = 200000, perBatch = 8192;
    double fill = 0.4;
    int threads = 8, rounds = 3;
    std::string precision = "half", lod = "preview", out = std::filesystem::temp_directory_path().string();
    for (int i = 1; i < argc; ++i) {
        const std::string k = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw Error(k + ": missing value");
            return argv[++i];
        };
        if (k == "--bricks") bricks = std::stoul(value());
        else if (k == "--fill") fill = std::stod(value());
        else if (k == "--threads") threads = std::stoi(value());
        else if (k == "--batch") perBatch = std::stoul(value());
        else if (k == "--precision") precision = value();
        else if (k == "--lod") lod = value();
        else if (k == "--rounds") rounds = std::stoi(value());
        else if (k == "--out") out = value();
        else throw Error("unknown option " + k);
    }
    const int bricksPerAxis = int(std::ceil(std::cbrt(double(bricks)))) + 1;
    VoxelGrid grid;
    grid.origin = glm::dvec3(0.0);
    grid.voxelSize = 1.0 / (bricksPerAxis * kBrickSize);
    grid.dims = glm::ivec3(bricksPerAxis * kBrickSize);
    const std::vector<PackedBricks> batches = makeBatches(bricks, fill, perBatch, bricksPerAxis);
    std::size_t active = 0;
    for (const PackedBricks& b : batches) active += b.voxels.size();
    const std::string path = out + "/yv_bench_encode_leaves.vdb";
    for (int round = 0; round < rounds; ++round) {
        VdbWriteOptions options;
        options.precision = parseVdbPrecision(precision);
        const LodLevels levels = lodLevelsFor(parseLodRequest(lod), grid);
        options.lodLevels = levels.last;
        options.lodFirstLevel = levels.first;
        VdbAssembler assembler(path, grid, Reduce::Mean, options);
        const auto start = std::chrono::steady_clock::now();
        std::atomic<std::size_t> next{0};
        std::vector<std::thread> writers;
        for (int t = 0; t < threads; ++t)
            writers.emplace_back([&] {
                for (std::size_t b; (b = next++) < batches.size();) assembler.add(batches[b], "batch " + std::to_string(b));
            });
        for (std::thread& w : writers) w.join();
        const double encode = since(start);
        const auto writeStart = std::chrono::steady_clock::now();
        assembler.write(VolumeMetadata{});
        const double write = since(writeStart);
        std::printf("{\"round\": %d, \"bricks\": %zu, \"active_voxels\": %zu, \"threads\": %d, \"precision\": \"%s\", "
                    "\"lod\": \"%s\", \"encode_s\": %.3f, \"write_s\": %.3f, \"encode_ns_per_voxel\": %.2f, "
                    "\"file_bytes\": %llu}\n",
                    round, bricks, active, threads, precision.c_str(), lod.c_str(), encode, write,
                    encode * 1e9 / double(active), (unsigned long long)std::filesystem::file_size(path));
        std::fflush(stdout);
        std::filesystem::remove(path);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_bench_encode_leaves: %s\n", e.what());
    return 1;
}
