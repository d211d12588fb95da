#include "vdb/lod_request.h"

#include "core/error.h"
#include "vdb/lod_pyramid.h"


namespace yv {

std::string toString(const LodRequest& request) {
    switch (request.kind) {
    case LodRequest::Kind::None: return "0";
    case LodRequest::Kind::Preview: return "preview";
    case LodRequest::Kind::Full: return std::to_string(request.levels);
    }
    return "?";
}

LodRequest parseLodRequest(const std::string& text) {
    if (text == "preview") return {};
    // Digits only: no sign, space or exponent.
    const bool digits = !text.empty() && text.size() <= 3 && text.find_first_not_of("0123456789") == std::string::npos;
    const int n = digits ? std::stoi(text) : -1;
    if (n < 0 || n > kMaxLodOption)
        throw Error("'" + text + "' is not preview (levels " + std::to_string(kPreviewFirstLevel) +
                    " to the coarsest), 0 (none) or a level count N from 1 to " + std::to_string(kMaxLodOption) +
                    " (every level 1..N)");
    return n == 0 ? LodRequest::none() : LodRequest::full(n);
}

LodLevels lodLevelsFor(const LodRequest& request, const VoxelGrid& grid) {
    switch (request.kind) {
    case LodRequest::Kind::None: return {};
    case LodRequest::Kind::Preview: {
        const int most = maxLodLevels(grid);
        if (most < kPreviewFirstLevel) return {};
        return {kPreviewFirstLevel, most};
    }
    case LodRequest::Kind::Full: return {1, checkedLodLevels(request.levels, grid)};
    }
    return {};
}

} // namespace yv
