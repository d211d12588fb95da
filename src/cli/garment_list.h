// Several garments in one `yarnvox voxelize` (the frames of an animation):
// the inputs from the command line and --list FILE, and the output, work dir
// and stats path of each, named after the input in the directories given.
#pragma once

#include <string>
#include <vector>

namespace yv {

/// One garment of a run of several, and where its results go.
struct GarmentJob {
    std::string input, output, workDir, statsPath;
};

/// The paths of a --list file: one per line; blank lines and lines starting
/// with '#' are skipped, surrounding spaces dropped, relative paths taken
/// from the list file's folder. Throws yv::Error naming the file and line
/// of a path that is not a readable file, or when the list names none.
std::vector<std::string> readGarmentList(const std::string& listPath);

/// The jobs of a run of several garments: DIR/STEM.EXT for -o DIR (created
/// when missing), DIR/STEM for --work-dir DIR, DIR/STEM.json for --stats DIR,
/// where STEM is the input's file name without its extension and EXT the
/// output format's. Throws yv::Error before any work when two inputs share a
/// stem or a directory cannot be made.
std::vector<GarmentJob> planGarmentJobs(const std::vector<std::string>& inputs, const std::string& outputDir,
                                        const std::string& extension, const std::string& workDirRoot,
                                        const std::string& statsDir);

} // namespace yv
