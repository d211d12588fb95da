#include "export/fiber_grids.h"

#include "core/error.h"

#include <filesystem>

namespace yv {

FiberGrids readFiberGrids(const std::string& path) {
    openvdb::initialize();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": no such file");
    openvdb::io::File file(path);
    try {
        file.open(/*delayLoad=*/false);
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not an OpenVDB file OpenVDB can read (" + e.what() + ")");
    }
    FiberGrids g;
    if (file.hasGrid("density")) g.density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    if (!g.density) {
        file.close();
        throw Error(path + ": has no float grid named 'density'");
    }
    if (file.hasGrid("orientation")) {
        g.orientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("orientation"));
        if (!g.orientation) {
            file.close();
            throw Error(path + ": its 'orientation' grid is not a vec3s grid");
        }
    }
    if (file.hasGrid("albedo")) {
        g.albedo = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("albedo"));
        if (!g.albedo) {
            file.close();
            throw Error(path + ": its 'albedo' grid is not a vec3s grid");
        }
    }
    file.close();
    return g;
}

} // namespace yv
