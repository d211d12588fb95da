#include "cli/output_format.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/output_path.h"
#include "export/fiber_grids.h"
#include "export/nanovdb_output.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace yv {
namespace {

bool endsWith(const std::string& s, const std::string& end) {
    return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

} // namespace

OutputFormat resolveOutputFormat(const std::string& format, const std::string& output, bool vdbAllowed) {
    std::string name = format;
    if (name.empty()) name = endsWith(output, ".vol") ? "vol" : endsWith(output, ".nvdb") ? "nvdb" : vdbAllowed ? "vdb" : "";
    if (name == "vol") return OutputFormat::Vol;
    if (name == "nvdb") return OutputFormat::Nvdb;
    if (name == "vdb" && vdbAllowed) return OutputFormat::Vdb;
    if (name.empty())
        throw Error("-o " + output + ": give --format vol or nvdb (or name the output .vol or .nvdb)");
    throw Error("--format " + name + ": not a format this command writes");
}

std::vector<std::string> exportPaths(OutputFormat format, const std::string& output, bool withOrientation,
                                     const VolExportOptions& volOptions, bool withAlbedo) {
    if (format == OutputFormat::Vol) return volOutputPaths(output, withOrientation, volOptions, withAlbedo);
    return {output};
}

void convertVdb(const std::string& vdbPath, OutputFormat format, const std::string& output,
                const VolExportOptions& volOptions, bool quiet) {
    // SIGINT or SIGTERM stops a long dense write between pieces, and the temporaries are removed.
    const InterruptScope interruptible;
    const FiberGrids grids = readFiberGrids(vdbPath);
    if (format == OutputFormat::Nvdb) {
        const NanoVdbExportResult r = exportNanoVdb(grids, output);
        if (!quiet)
            std::printf("wrote %s (NanoVDB, %d grid%s, %llu bytes)\n", output.c_str(), r.grids, r.grids > 1 ? "s" : "",
                        static_cast<unsigned long long>(r.bytes));
        return;
    }
    YV_CHECK(format == OutputFormat::Vol);
    const VolExportResult r = exportMitsubaVol(grids, output, volOptions);
    if (!quiet) {
        const glm::ivec3 d = r.box.dims();
        std::printf("exported voxels [%d, %d) x [%d, %d) x [%d, %d) (%d x %d x %d), box (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n",
                    r.box.min.x, r.box.max.x, r.box.min.y, r.box.max.y, r.box.min.z, r.box.max.z, d.x, d.y, d.z,
                    r.worldMin.x, r.worldMin.y, r.worldMin.z, r.worldMax.x, r.worldMax.y, r.worldMax.z);
        for (const std::string& p : r.paths) std::printf("wrote %s\n", p.c_str());
        if (!grids.orientation) std::printf("note: %s has no 'orientation' grid: only the density was exported\n", vdbPath.c_str());
    }
    if (r.densityClamped > 0)
        std::fprintf(stderr, "warning: %llu voxels held a density above 1 and were written as 255 (uint8 holds 0 to 1)\n",
                     static_cast<unsigned long long>(r.densityClamped));
}

void voxelizeInFormat(const std::string& format, const std::string& output, const std::string& input, bool quiet,
                      const std::function<void(const std::string& vdbPath)>& voxelize) {
    const OutputFormat f = resolveOutputFormat(format, output, true);
    if (f == OutputFormat::Vdb) {
        voxelize(output);
        return;
    }
    // Every file the conversion writes is checked before minutes of voxelizing.
    const VolExportOptions volOptions;
    // OUT.albedo.vol too, which only runs with --albedo write: checking it always refuses nothing a run needs.
    for (const std::string& p : exportPaths(f, output, true, volOptions, true)) checkOutputPath(p, "-o", {input});
    const std::string vdb = output + ".partial-" + std::to_string(::getpid()) + ".vdb";
    struct RemoveOnExit {
        std::string path;
        ~RemoveOnExit() {
            std::error_code ec;
            std::filesystem::remove(path, ec);
        }
    } removeVdb{vdb};
    voxelize(vdb);
    convertVdb(vdb, f, output, volOptions, quiet);
}

} // namespace yv
