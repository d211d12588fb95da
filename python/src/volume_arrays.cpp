#include "volume_arrays.h"

#include "core/error.h"

#include <openvdb/openvdb.h>
#include <pybind11/numpy.h>

#include <cstring>
#include <mutex>

namespace py = pybind11;

namespace yv::python {
namespace {

/// The grids of one level, as OpenVDB reads them (half-precision files come back as float).
struct LevelGrids {
    openvdb::FloatGrid::Ptr density;
    openvdb::Vec3SGrid::Ptr orientation, albedo; ///< null when the file has none
};

std::string levelName(const std::string& grid, int level) {
    return level == 0 ? grid : grid + "_lod" + std::to_string(level);
}

void openFile(openvdb::io::File& file, const std::string& path) {
    static std::once_flag initialized;
    std::call_once(initialized, [] { openvdb::initialize(); });
    try {
        file.open(false); // no delayed loading: the file may go once read
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": not a readable OpenVDB file (" + e.what() + ")");
    }
}

LevelGrids readLevel(const std::string& path, int level) {
    if (level < 0) throw Error(path + ": level " + std::to_string(level) + " is not a level (0 or more)");
    openvdb::io::File file(path);
    openFile(file, path);
    const auto grid = [&](const std::string& name) -> openvdb::GridBase::Ptr {
        return file.hasGrid(name) ? file.readGrid(name) : nullptr;
    };
    LevelGrids g;
    g.density = openvdb::gridPtrCast<openvdb::FloatGrid>(grid(levelName("density", level)));
    if (!g.density) throw Error(path + ": no float grid " + levelName("density", level));
    g.orientation = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid(levelName("orientation", level)));
    g.albedo = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid(levelName("albedo", level)));
    file.close();
    return g;
}

/// What both layouts share: the voxel size and the index-to-world matrix
/// (row-major, column vectors: world = M * (i, j, k, 1)).
py::dict frameOf(const LevelGrids& g) {
    py::dict out;
    const openvdb::math::Transform& t = g.density->transform();
    out["voxel_size"] = t.voxelSize()[0];
    py::array_t<double> m({4, 4});
    const openvdb::Mat4d affine = t.baseMap()->getAffineMap()->getMat4();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m.mutable_at(r, c) = affine(c, r); // OpenVDB's matrices act on row vectors
    out["index_to_world"] = m;
    return out;
}

} // namespace

py::dict readDenseVolume(const std::string& path, int level, const std::optional<std::array<int, 6>>& box) {
    const LevelGrids g = readLevel(path, level);
    openvdb::CoordBBox b;
    if (box) {
        const auto& v = *box;
        if (v[3] <= v[0] || v[4] <= v[1] || v[5] <= v[2])
            throw Error("box holds no voxel (the maximum is exclusive and must exceed the minimum)");
        b = openvdb::CoordBBox(openvdb::Coord(v[0], v[1], v[2]), openvdb::Coord(v[3] - 1, v[4] - 1, v[5] - 1));
    } else {
        b = g.density->evalActiveVoxelBoundingBox();
        if (b.empty()) b = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(-1)); // an empty grid: a 0^3 box
    }
    const openvdb::Coord lo = b.min();
    const std::array<py::ssize_t, 3> dims{b.empty() ? 0 : b.dim().x(), b.empty() ? 0 : b.dim().y(),
                                          b.empty() ? 0 : b.dim().z()};
    py::array_t<float> density(dims);
    std::memset(density.mutable_data(), 0, density.nbytes());
    const auto vectors = [&](const openvdb::Vec3SGrid::Ptr& grid) -> py::object {
        if (!grid) return py::none();
        py::array_t<float> a({dims[0], dims[1], dims[2], py::ssize_t(3)});
        std::memset(a.mutable_data(), 0, a.nbytes());
        auto w = a.mutable_unchecked<4>();
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            if (!b.isInside(c)) continue;
            for (int k = 0; k < 3; ++k) w(c.x() - lo.x(), c.y() - lo.y(), c.z() - lo.z(), k) = (*it)[k];
        }
        return a;
    };
    {
        auto w = density.mutable_unchecked<3>();
        for (auto it = g.density->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            if (b.isInside(c)) w(c.x() - lo.x(), c.y() - lo.y(), c.z() - lo.z()) = *it;
        }
    }
    py::dict out = frameOf(g);
    out["origin"] = py::make_tuple(lo.x(), lo.y(), lo.z());
    out["density"] = density;
    out["orientation"] = vectors(g.orientation);
    out["albedo"] = vectors(g.albedo);
    return out;
}

py::dict readSparseVolume(const std::string& path, int level) {
    const LevelGrids g = readLevel(path, level);
    const auto& tree = g.density->constTree();
    const py::ssize_t n = py::ssize_t(tree.leafCount());
    py::array_t<std::int32_t> origins({n, py::ssize_t(3)});
    py::array_t<float> density({n, py::ssize_t(8), py::ssize_t(8), py::ssize_t(8)});
    py::array_t<bool> active({n, py::ssize_t(8), py::ssize_t(8), py::ssize_t(8)});
    const auto vectorArray = [&](const openvdb::Vec3SGrid::Ptr& grid) -> py::object {
        if (!grid) return py::none();
        py::array_t<float> a({n, py::ssize_t(8), py::ssize_t(8), py::ssize_t(8), py::ssize_t(3)});
        std::memset(a.mutable_data(), 0, a.nbytes());
        return a;
    };
    py::object orientation = vectorArray(g.orientation), albedo = vectorArray(g.albedo);
    // A leaf's value n is voxel (x, y, z) = (n >> 6, (n >> 3) & 7, n & 7) of
    // the leaf: its 512 values in order are the [x][y][z] array.
    const auto copyVectors = [](const openvdb::Vec3SGrid::Ptr& grid, py::object& into, py::ssize_t i,
                                const openvdb::Coord& origin) {
        if (!grid) return;
        const auto* leaf = grid->constTree().probeConstLeaf(origin);
        if (!leaf) return;
        float* out = into.cast<py::array_t<float>>().mutable_data() + i * 512 * 3;
        for (openvdb::Index v = 0; v < 512; ++v)
            if (leaf->isValueOn(v))
                for (int k = 0; k < 3; ++k) out[v * 3 + k] = leaf->getValue(v)[k];
    };
    py::ssize_t i = 0;
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf, ++i) {
        const openvdb::Coord o = leaf->origin();
        for (int k = 0; k < 3; ++k) origins.mutable_at(i, k) = o[k];
        float* d = density.mutable_data() + i * 512;
        bool* a = active.mutable_data() + i * 512;
        for (openvdb::Index v = 0; v < 512; ++v) {
            a[v] = leaf->isValueOn(v);
            d[v] = a[v] ? leaf->getValue(v) : 0.0f;
        }
        copyVectors(g.orientation, orientation, i, o);
        copyVectors(g.albedo, albedo, i, o);
    }
    py::dict out = frameOf(g);
    out["origins"] = origins;
    out["density"] = density;
    out["active"] = active;
    out["orientation"] = orientation;
    out["albedo"] = albedo;
    return out;
}

py::dict readVolumeMetadata(const std::string& path) {
    openvdb::io::File file(path);
    openFile(file, path);
    py::dict out;
    const openvdb::MetaMap::Ptr meta = file.getMetadata();
    for (auto it = meta->beginMeta(); it != meta->endMeta(); ++it) {
        const openvdb::Metadata& m = *it->second;
        if (const auto* v = dynamic_cast<const openvdb::StringMetadata*>(&m)) out[it->first.c_str()] = v->value();
        else if (const auto* v = dynamic_cast<const openvdb::Int32Metadata*>(&m)) out[it->first.c_str()] = v->value();
        else if (const auto* v = dynamic_cast<const openvdb::Int64Metadata*>(&m)) out[it->first.c_str()] = v->value();
        else if (const auto* v = dynamic_cast<const openvdb::DoubleMetadata*>(&m)) out[it->first.c_str()] = v->value();
        else if (const auto* v = dynamic_cast<const openvdb::FloatMetadata*>(&m)) out[it->first.c_str()] = v->value();
        else if (const auto* v = dynamic_cast<const openvdb::BoolMetadata*>(&m)) out[it->first.c_str()] = v->value();
        else out[it->first.c_str()] = m.str();
    }
    file.close();
    return out;
}

} // namespace yv::python
