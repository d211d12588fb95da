// Per-voxel density statistics of a .vdb file's float "density" grid, read
// through OpenVDB itself: active voxels, mass, maximum, percentiles and the
// share of voxels above 1, one JSON object on stdout. The benchmarks use it
// to show what a voxelization holds voxel by voxel, not only in sum.
//
//   yv_density_stats FILE.vdb [GRID_NAME]
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: yv_density_stats FILE.vdb [GRID_NAME]\n");
        return 2;
    }
    const std::string name = argc > 2 ? argv[2] : "density";
    openvdb::initialize();
    openvdb::io::File file(argv[1]);
    file.open();
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
    file.close();
    if (!grid) throw std::runtime_error(std::string(argv[1]) + ": grid '" + name + "' is not a float grid");
    std::vector<float> values;
    values.reserve(grid->activeVoxelCount());
    double sum = 0.0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        values.push_back(*it);
        sum += *it;
    }
    std::sort(values.begin(), values.end());
    auto pct = [&](double p) { return values.empty() ? 0.0 : double(values[std::size_t(p * double(values.size() - 1))]); };
    const std::size_t above = values.end() - std::upper_bound(values.begin(), values.end(), 1.0f + 1.0f / 1024.0f);
    const double h = grid->voxelSize()[0];
    std::printf("{ \"file\": \"%s\", \"active_voxels\": %zu, \"mass\": %.9g, \"max\": %.6g, \"p50\": %.6g, "
                "\"p90\": %.6g, \"p99\": %.6g, \"p999\": %.6g, \"share_above_1\": %.6g }\n",
                argv[1], values.size(), sum * h * h * h, values.empty() ? 0.0 : double(values.back()), pct(0.5),
                pct(0.9), pct(0.99), pct(0.999), values.empty() ? 0.0 : double(above) / double(values.size()));
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "yv_density_stats: error: %s\n", e.what());
    return 1;
}
