#include "export/nanovdb_output.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "export/pending_file_buf.h"

#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include <filesystem>
#include <ostream>
#include <vector>

namespace yv {

NanoVdbExportResult exportNanoVdb(const FiberGrids& grids, const std::string& path) {
    YV_CHECK(grids.density);
    std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>> handles;
    // The converter keeps the grid's name and maps OpenVDB's fog volume class
    // to NanoVDB's; statistics (bounds, min, max) and checksums are its defaults.
    handles.push_back(nanovdb::openToNanoVDB(*grids.density));
    if (grids.orientation) handles.push_back(nanovdb::openToNanoVDB(*grids.orientation));
    if (grids.albedo) handles.push_back(nanovdb::openToNanoVDB(*grids.albedo));

    std::uint64_t need = 0;
    for (const auto& h : handles) need += h.size();
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    const std::string dir = parent.empty() ? "." : parent.string();
    std::error_code ec;
    const std::filesystem::space_info space = std::filesystem::space(dir, ec);
    if (ec) throw Error(path + ": cannot tell the free space in " + dir + ": " + ec.message());
    // Headers and grid names come on top of the grids: a few hundred bytes.
    if (need + 4096 > space.available)
        throw Error(path + ": the NanoVDB grids take " + std::to_string(need) + " bytes, and " + dir + " has " +
                    std::to_string(space.available) + " bytes free: nothing was written");

    signalAtTestPoint("nvdb-write");
    const std::string stopped = "while writing " + path + ": nothing was written; run the command again";
    throwIfInterrupted(stopped);
    PendingFile file(path);
    PendingFileBuf buffer(file);
    std::ostream os(&buffer);
    try {
        nanovdb::io::writeGrids(os, handles, nanovdb::io::Codec::NONE);
    } catch (const std::exception& e) {
        throw Error(path + ": NanoVDB could not write the grids: " + e.what());
    }
    if (!buffer.error().empty()) throw Error(buffer.error());
    if (!os) throw Error(path + ": NanoVDB could not write the grids");
    throwIfInterrupted(stopped); // a signal during the write: the file is not published
    file.publish();
    return {file.size(), int(handles.size())};
}

} // namespace yv
