// What the .vdb leaf stream's last take costs (vdb/leaf_stream.h): once the
// last region is done, every leaf still pending in the regions' batches is
// put in tree order after the leaves taken before, and the disk waits for
// it. Synthetic leaves: `--taken` already in order, `--pending` spread over
// `--batches` sorted batches. Two ways, alternating:
//   gathered: the batches' leaves copied into one vector, sorted
//             (sortInTreeOrder), then appended (what LeafStream did at a6e9a66);
//   in place: appendInTreeOrder over the batches' ranges, into room reserved
//             for every leaf given (what it does now).
//
//   yv_bench_leaf_take [--taken 1000000] [--pending 1000000] [--batches 150] [--rounds 3]
// Prints one JSON line a round and way: seconds, and the leaves per second.
#include "core/error.h"
#include "vdb/leaf_batches.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <span>
#include <string>
#include <vector>

using namespace yv;

namespace {

double since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main(int argc, char** argv) {
    std::size_t taken = 1000000, pending = 1000000, batchCount = 150;
    int rounds = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const long v = std::atol(argv[i + 1]);
        if (k == "--taken") taken = std::size_t(v);
        else if (k == "--pending") pending = std::size_t(v);
        else if (k == "--batches") batchCount = std::size_t(std::max(1l, v));
        else if (k == "--rounds") rounds = int(v);
        else {
            std::fprintf(stderr, "yv_bench_leaf_take: unknown option %s\n", k.c_str());
            return 2;
        }
    }
    std::mt19937_64 random(5);
    // Taken leaves hold orders below 2^40; pending ones above, each batch sorted.
    std::vector<LeafRecord> before(taken);
    for (std::size_t i = 0; i < taken; ++i) before[i].order = i;
    std::vector<std::vector<LeafRecord>> batches(batchCount);
    for (std::size_t i = 0; i < pending; ++i) {
        LeafRecord r;
        r.order = (std::uint64_t(1) << 40) + random() % (pending * 8);
        r.source = std::uint32_t(i % batchCount);
        r.at[0] = i;
        batches[i % batchCount].push_back(r);
    }
    for (std::vector<LeafRecord>& b : batches)
        std::sort(b.begin(), b.end(), inTreeOrder);
    std::printf("{\"taken\": %zu, \"pending\": %zu, \"batches\": %zu, \"record_bytes\": %zu}\n", taken, pending,
                batchCount, sizeof(LeafRecord));
    for (int round = 0; round < rounds; ++round)
        for (const char* way : {"gathered", "in place"}) {
            std::vector<LeafRecord> leaves = before; // capacity: the taken ones, as after earlier takes
            const auto start = std::chrono::steady_clock::now();
            if (std::string(way) == "gathered") {
                std::vector<LeafRecord> ready;
                for (const std::vector<LeafRecord>& b : batches) ready.insert(ready.end(), b.begin(), b.end());
                sortInTreeOrder(ready);
                leaves.insert(leaves.end(), ready.begin(), ready.end());
            } else {
                std::vector<std::span<const LeafRecord>> pieces(batches.begin(), batches.end());
                leaves.reserve(std::max(taken + pending, 2 * leaves.capacity()));
                appendInTreeOrder(pieces, leaves);
            }
            const double seconds = since(start);
            YV_CHECK(leaves.size() == taken + pending && std::is_sorted(leaves.begin(), leaves.end(), inTreeOrder));
            std::printf("{\"round\": %d, \"way\": \"%s\", \"seconds\": %.4f, \"leaves_per_s\": %.0f}\n", round, way,
                        seconds, double(pending) / seconds);
        }
    return 0;
}
