#include "vdb/region_metadata.h"

#include "core/error.h"

#include <sstream>

namespace yv {

std::string encodeRegions(const std::vector<RecordedRegion>& regions) {
    std::string out;
    for (const RecordedRegion& r : regions) {
        if (!out.empty()) out += ';';
        out += std::to_string(r.id);
        for (const int v : {r.min.x, r.min.y, r.min.z, r.max.x, r.max.y, r.max.z}) out += ' ' + std::to_string(v);
        out += ' ' + std::to_string(r.activeVoxels);
    }
    return out;
}

std::vector<RecordedRegion> decodeRegions(const std::string& text, const std::string& where) {
    std::vector<RecordedRegion> out;
    std::istringstream entries(text);
    for (std::string entry; std::getline(entries, entry, ';');) {
        std::istringstream in(entry);
        RecordedRegion r;
        std::string rest;
        in >> r.id >> r.min.x >> r.min.y >> r.min.z >> r.max.x >> r.max.y >> r.max.z >> r.activeVoxels;
        const bool bad = in.fail() || (in >> rest, !rest.empty());
        if (bad || r.max.x <= r.min.x || r.max.y <= r.min.y || r.max.z <= r.min.z)
            throw Error(where + ": region entry " + std::to_string(out.size() + 1) + " '" + entry +
                        "' is not 'ID MINX MINY MINZ MAXX MAXY MAXZ ACTIVE' with min below max");
        out.push_back(r);
    }
    return out;
}

} // namespace yv
