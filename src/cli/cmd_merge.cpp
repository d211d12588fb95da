// `yarnvox merge`: a finished work directory to one .vdb (voxelize does this
// itself at its end; this re-runs it, e.g. after a merge failed for disk space).
#include "cli/commands.h"
#include "cli/interruptible.h"
#include "cli/option_checks.h"
#include "cli/option_words.h"
#include "pipeline/run_fingerprint.h"
#include "core/interrupt.h"
#include "core/output_path.h"
#include "store/brick_store.h"
#include "vdb/merge.h"
#include "vdb/spill_file.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>

namespace yv {

namespace {

struct MergeArgs {
    std::string workDir, output;
    VdbCompression compression = VdbCompression::ActiveMask;
    VdbPrecision precision = kDefaultVdbPrecision;
    LodRequest lod;
    bool quiet = false;
};

/// Merges the work dir into the .vdb; a signal leaves the work dir as it was and no .vdb.
void runMerge(const MergeArgs& a) {
    const auto start = std::chrono::steady_clock::now();
    checkOutputPath(a.output, "-o", {});
    const StoreManifest manifest = readManifest(a.workDir);
    VdbWriteOptions options;
    options.compression = a.compression;
    options.precision = a.precision;
    // Checked against the store's grid before any region is read.
    const LodLevels lod = lodLevelsFor(a.lod, manifest.grid);
    options.lodFirstLevel = lod.first;
    options.lodLevels = lod.last;
    options.streamLeaves = streamLeavesFromEnvironment();
    options.scratchMemoryBytes = spillMemoryBytes();
    const VolumeMetadata metadata = manifest.run;
    options.albedo = metadata.albedo; // the run's bricks carry it: so does the merged file
    saysWhatWasKept("while merging " + a.workDir,
                    a.output + " was not written and " + a.workDir + " is unchanged; go on with: " + commandLine(),
                    [&] { mergeStoreToVdb(a.workDir, a.output, metadata, options); });
    if (!a.quiet)
        std::printf("merged %s -> %s in %.2f s\n", a.workDir.c_str(), a.output.c_str(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

} // namespace

void addMergeCommand(CLI::App& app) {
    auto args = std::make_shared<MergeArgs>();
    CLI::App* cmd = app.add_subcommand("merge", "Merge the brick store of a finished voxelize run into one OpenVDB file");
    cmd->add_option("workdir", args->workDir, "Work directory of a voxelize run (--work-dir)")->required()->check(CLI::ExistingDirectory);
    cmd->add_option("-o,--output", args->output, "Output .vdb file")->required();
    cmd->add_option("--vdb-compression", args->compression, "mask, blosc, zip or none (as voxelize's option)")
        ->default_str("mask")
        ->transform(oneOf(kCompressionWords));
    cmd->add_option("--precision", args->precision, "half or float: how the grids' values are stored (as voxelize's option)")
        ->default_str(toString(kDefaultVdbPrecision))
        ->transform(oneOf(kPrecisionWords));
    cmd->add_option_function<std::string>(
           "--lod", [args](const std::string& text) { args->lod = parseLodRequest(text); },
           "Level-of-detail grids: preview (levels 3 to the coarsest), 0 (none) or N (every level 1..N), as "
           "voxelize's option")
        ->default_str("preview")
        ->check(lodWords());
    cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
    cmd->callback([args] { runInterruptible(args->output + " is whole", [&] { runMerge(*args); }); });
}

} // namespace yv
