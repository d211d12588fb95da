// The formats a volume can be written in (--format vdb|vol|nvdb): `voxelize`
// writes a .vdb and, for vol and nvdb, converts it; `export` converts an
// existing one. Conversions start from the leaves in the .vdb, never from a
// second voxelization.
#pragma once

#include "export/mitsuba_vol.h"

#include <functional>
#include <string>
#include <vector>

namespace yv {

enum class OutputFormat { Vdb, Vol, Nvdb };

/// `format` ("vdb", "vol", "nvdb") or, when empty, the output's extension
/// (.vol, .nvdb; anything else is a .vdb when `vdbAllowed`). Throws yv::Error
/// when neither names a format that can be written here.
OutputFormat resolveOutputFormat(const std::string& format, const std::string& output, bool vdbAllowed);

/// Every file a conversion to `format` writes for output `output`.
std::vector<std::string> exportPaths(OutputFormat format, const std::string& output, bool withOrientation,
                                     const VolExportOptions& volOptions, bool withAlbedo = false);

/// Converts the grids of the .vdb at `vdbPath` to `output` in `format` (vol
/// or nvdb) and prints what it wrote unless `quiet`.
void convertVdb(const std::string& vdbPath, OutputFormat format, const std::string& output,
                const VolExportOptions& volOptions, bool quiet);

/// `voxelize --format vol|nvdb`: checks every output path, runs `voxelize`
/// into a temporary .vdb beside the output, converts it, and removes it
/// (also when the run or the conversion fails). For vdb, just `voxelize(output)`.
void voxelizeInFormat(const std::string& format, const std::string& output, const std::string& input, bool quiet,
                      const std::function<void(const std::string& vdbPath)>& voxelize);

} // namespace yv
