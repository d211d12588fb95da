// The slices a voxelize run placed, found again for `inspect --render
// slices`: the garment and slice options its work directory's manifest or
// its .vdb's metadata record (or a garment given on the command line), and
// the run's voxel grid, so the slices land where the voxels are.
#pragma once

#include "garment/slices.h"
#include "plan/grid.h"

#include <map>
#include <string>
#include <vector>

namespace yv {

/// What the command line adds to what the run recorded.
struct RunSlicesOptions {
    std::string garment;     ///< --garment: this .bcc instead of the one the run names
    double yarnRadius = 0.0; ///< --yarn-radius: world units (0: as recorded, else the garment file's)
};

struct RunSlices {
    SlicePlan plan;
    VoxelGrid grid;                 ///< the volume's grid (origin and voxel size)
    std::string garmentPath;
    std::vector<std::string> notes; ///< what was assumed, one line each
    /// What the run recorded, as text: core/run_metadata.h's fields (and a
    /// .vdb's other file metadata, such as "reduce").
    std::map<std::string, std::string> recorded;
};

/// The number the run recorded under `key` (RunSlices::recorded), or
/// `fallback` where it recorded none. Throws yv::Error naming `where` when
/// the text is not a number, all of it.
double recordedNumber(const std::map<std::string, std::string>& recorded, const std::string& key, double fallback,
                      const std::string& where);

/// The slices of the run that made `input` (a work directory or a .vdb).
/// Throws yv::Error naming `input` when no garment can be found (a foreign
/// .vdb without --garment, a garment file that moved) or none of the yarn
/// radius, the grid or the garment can be read.
RunSlices loadRunSlices(const std::string& input, const RunSlicesOptions& options);

} // namespace yv
