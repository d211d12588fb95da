#include "inspect/isosurface_mesh.h"

#include "core/atomic_file.h"
#include "core/bricks.h"
#include "core/error.h"
#include "core/interrupt.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <bit>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <unordered_set>

namespace yv {
namespace {

int floorDiv8(int v) { return v >= 0 ? v / 8 : -((-v + 7) / 8); }

/// Occupied bricks inside `box` (brick coordinates [lo, hi)).
void boxBricks(const VoxelBox& box, glm::ivec3& lo, glm::ivec3& hi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = floorDiv8(box.min[a]);
        hi[a] = floorDiv8(box.max[a] + 7);
    }
}

std::string extensionOf(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

void append(std::vector<std::uint8_t>& out, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    out.insert(out.end(), p, p + bytes);
}

} // namespace

void checkMeshPath(const std::string& path) {
    const std::string e = extensionOf(path);
    if (e != ".ply" && e != ".obj") throw Error("--mesh " + path + ": expected a .ply or .obj file name");
}

std::uint64_t estimateMeshTriangles(const VolumeSource& source, const VoxelBox& box, int level) {
    glm::ivec3 lo, hi;
    boxBricks(box, lo, hi);
    std::unordered_set<std::uint64_t> levelBricks;
    for (const glm::ivec3& c : source.occupiedBricks()) {
        if (glm::any(glm::lessThan(c, lo)) || glm::any(glm::greaterThanEqual(c, hi))) continue;
        const glm::ivec3 b = c >> level; // arithmetic shift: floor for negative coordinates too
        levelBricks.insert((std::uint64_t(std::uint32_t(b.x) & 0x1fffff) << 42) |
                           (std::uint64_t(std::uint32_t(b.y) & 0x1fffff) << 21) | std::uint64_t(std::uint32_t(b.z) & 0x1fffff));
    }
    return 384u * std::uint64_t(levelBricks.size());
}

IsosurfaceMesh extractIsosurface(const VolumeSource& source, const VoxelBox& box, double isoValue, int level) {
    openvdb::initialize();
    glm::ivec3 lo, hi;
    boxBricks(box, lo, hi);
    const int scale = 1 << level;
    auto grid = openvdb::FloatGrid::create(0.0f);
    openvdb::FloatTree& tree = grid->tree();
    if (level == 0) {
        // Whole leaves, never voxel by voxel: a brick is an OpenVDB leaf, in the same voxel order.
        source.forEachBrick(lo, hi, [&](const SourceBrick& b) {
            auto* leaf = new openvdb::FloatTree::LeafNodeType(openvdb::Coord(b.coord.x * 8, b.coord.y * 8, b.coord.z * 8), 0.0f);
            for (int i = 0; i < kBrickVoxels; ++i)
                if (b.density[i] != 0.0f) leaf->setValueOn(openvdb::Index(i), b.density[i]);
            tree.addLeaf(leaf);
        });
    } else {
        const float weight = 1.0f / float(scale * scale * scale);
        openvdb::FloatGrid::Accessor acc = grid->getAccessor();
        source.forEachBrick(lo, hi, [&](const SourceBrick& b) {
            for (int x = 0; x < 8; ++x)
                for (int y = 0; y < 8; ++y)
                    for (int z = 0; z < 8; ++z) {
                        const float d = b.density[brickOffset(x, y, z)];
                        if (d == 0.0f) continue;
                        const glm::ivec3 q = (b.coord * 8 + glm::ivec3(x, y, z)) >> level;
                        acc.modifyValue(openvdb::Coord(q.x, q.y, q.z), [&](float& v) { v += d * weight; });
                    }
        });
    }
    // Level voxel q covers [q, q+1) * scale full-resolution voxels: its value sits at its centre.
    openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(double(scale));
    xform->postTranslate(openvdb::Vec3d(0.5 * scale));
    grid->setTransform(xform);

    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, triangles, quads, isoValue, 0.0);
    if (points.empty())
        throw Error("no voxel reaches the iso value " + std::to_string(isoValue) + (level ? " at level " + std::to_string(level) : std::string()) +
                    ": the isosurface is empty (a lower --iso)");
    IsosurfaceMesh mesh;
    mesh.vertices.reserve(points.size());
    for (const openvdb::Vec3s& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
    // OpenVDB orients its polygons for a level set (inside below the iso
    // value); inside a density grid lies above it, so each winding is reversed.
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    for (const openvdb::Vec3I& t : triangles) mesh.triangles.push_back({t[0], t[2], t[1]});
    for (const openvdb::Vec4I& q : quads) {
        mesh.triangles.push_back({q[0], q[2], q[1]});
        mesh.triangles.push_back({q[0], q[3], q[2]});
    }
    return mesh;
}

void writeMesh(const std::string& path, const IsosurfaceMesh& mesh) {
    checkMeshPath(path);
    std::vector<std::uint8_t> bytes;
    if (extensionOf(path) == ".ply") {
        const std::string header = "ply\nformat binary_little_endian 1.0\ncomment yarnvox isosurface, voxel coordinates\n"
                                   "element vertex " + std::to_string(mesh.vertices.size()) +
                                   "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                                   std::to_string(mesh.triangles.size()) +
                                   "\nproperty list uchar int vertex_indices\nend_header\n";
        bytes.reserve(header.size() + mesh.vertices.size() * 12 + mesh.triangles.size() * 13);
        append(bytes, header.data(), header.size());
        static_assert(std::endian::native == std::endian::little, "PLY is written as the host's bytes");
        append(bytes, mesh.vertices.data(), mesh.vertices.size() * sizeof(glm::vec3));
        for (const auto& t : mesh.triangles) {
            const std::uint8_t n = 3;
            const std::int32_t idx[3] = {std::int32_t(t[0]), std::int32_t(t[1]), std::int32_t(t[2])};
            append(bytes, &n, 1);
            append(bytes, idx, sizeof idx);
        }
    } else {
        std::string text = "# yarnvox isosurface, voxel coordinates\n";
        char line[96];
        for (const glm::vec3& v : mesh.vertices) {
            const int n = std::snprintf(line, sizeof line, "v %.7g %.7g %.7g\n", double(v.x), double(v.y), double(v.z));
            text.append(line, std::size_t(n));
        }
        for (const auto& t : mesh.triangles) {
            const int n = std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
            text.append(line, std::size_t(n));
        }
        append(bytes, text.data(), text.size());
    }
    signalAtTestPoint("mesh-write");
    throwIfInterrupted("before " + path + " was written: it was not written; run the command again");
    writeFileAtomically(path, bytes);
}

} // namespace yv
