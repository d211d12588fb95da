#include "inspect/mesh_report.h"

#include "core/error.h"
#include "core/output_path.h"
#include "core/stats.h"
#include "inspect/isosurface_mesh.h"
#include "inspect/report_text.h"

#include <algorithm>
#include <memory>

namespace yv {
namespace {

/// The refusal of a full-resolution mesh above the limit, naming the
/// coarsest level that fits.
Error tooLarge(const MeshRequest& r, const VolumeSource& source, const VoxelBox& box, std::uint64_t estimate) {
    int coarser = 1;
    while (coarser < 21 && estimateMeshTriangles(source, box, coarser) > kMeshTriangleLimit) ++coarser;
    return Error("--mesh " + r.mesh + ": the full-resolution isosurface would have about " +
                 std::to_string(estimate / 1000000) + " million triangles (about " + bytesText(double(estimate) * 19.0) +
                 " as PLY), above the " + std::to_string(kMeshTriangleLimit / 1000000) +
                 " million written without --mesh-level; give --mesh-level " + std::to_string(coarser) + " (about " +
                 std::to_string(estimateMeshTriangles(source, box, coarser) / 1000000) + " million) or coarser");
}

} // namespace

std::string meshToFile(const MeshRequest& r) {
    checkMeshPath(r.mesh);
    checkOutputPath(r.mesh, "--mesh", {r.input});
    const std::unique_ptr<VolumeSource> source = openVolumeSource(r.input);
    if (source->occupiedBricks().empty()) throw Error("nothing to mesh: the volume has no active voxels");
    const VoxelBox box = r.region ? source->regionBounds(*r.region) : source->bounds();
    const int level = r.level.value_or(0);
    const std::uint64_t estimate = estimateMeshTriangles(*source, box, level);
    if (!r.level && estimate > kMeshTriangleLimit) throw tooLarge(r, *source, box, estimate);
    const IsosurfaceMesh mesh = extractIsosurface(*source, box, r.iso, level);
    writeMesh(r.mesh, mesh);
    std::string out;
    if (r.json)
        return JsonObject()
                   .set("path", r.input)
                   .set("mesh", r.mesh)
                   .set("iso", r.iso)
                   .set("level", level)
                   .set("vertices", std::uint64_t(mesh.vertices.size()))
                   .set("triangles", std::uint64_t(mesh.triangles.size()))
                   .dump() +
               "\n";
    appendf(out, "%s: isosurface at density %g%s, %zu vertices, %zu triangles (voxel coordinates)\n", r.mesh.c_str(), r.iso,
            level ? (", level " + std::to_string(level)).c_str() : "", mesh.vertices.size(), mesh.triangles.size());
    return out;
}

} // namespace yv
