#include "inspect/render_request.h"

#include "core/error.h"

namespace yv {

const char* renderKindName(RenderKind kind) {
    switch (kind) {
    case RenderKind::Raycast: return "raycast";
    case RenderKind::Mip: return "mip";
    case RenderKind::Cut: return "cut";
    case RenderKind::Orientation: return "orientation";
    case RenderKind::Slices: return "slices";
    case RenderKind::TextureSlicing: return "texture-slicing";
    case RenderKind::HalfAngle: return "half-angle";
    case RenderKind::Splatting: return "splatting";
    case RenderKind::Isosurface: return "isosurface";
    case RenderKind::VolumetricTriangles: return "volumetric-triangles";
    }
    return "raycast";
}

const std::vector<RenderKind>& renderKinds() {
    static const std::vector<RenderKind> kinds = {
        RenderKind::Raycast,   RenderKind::Mip,       RenderKind::Cut,        RenderKind::Orientation,
        RenderKind::Slices,    RenderKind::TextureSlicing, RenderKind::HalfAngle, RenderKind::Splatting,
        RenderKind::Isosurface, RenderKind::VolumetricTriangles};
    return kinds;
}

RenderKind parseRenderKind(const std::string& text) {
    for (const RenderKind kind : renderKinds())
        if (text == renderKindName(kind)) return kind;
    throw Error("--render '" + text +
                "': expected raycast, mip, cut, orientation, slices, texture-slicing, half-angle, splatting, "
                "isosurface or volumetric-triangles");
}

bool marchesRays(RenderKind kind) {
    return kind == RenderKind::Raycast || kind == RenderKind::Mip || kind == RenderKind::Orientation ||
           kind == RenderKind::Isosurface;
}

SlicePrimitive parseSlicePrimitive(const std::string& text) {
    if (text == "auto") return SlicePrimitive::Auto;
    if (text == "tiles") return SlicePrimitive::Tiles;
    if (text == "points") return SlicePrimitive::Points;
    if (text == "boxes") return SlicePrimitive::Boxes;
    throw Error("--slice-primitive '" + text + "': expected auto, tiles, points or boxes");
}

bool drawsPlanes(RenderKind kind) { return kind == RenderKind::TextureSlicing || kind == RenderKind::HalfAngle; }

} // namespace yv
