// The .vdb writer's options by name (--vdb-compression, --precision), and
// the archive flags OpenVDB gives each compression.
#include "vdb/vdb_writer.h"

#include "core/environment_count.h"
#include "core/error.h"

#include <openvdb/openvdb.h>

namespace yv {

const char* toString(VdbCompression c) {
    switch (c) {
    case VdbCompression::Blosc: return "blosc";
    case VdbCompression::Zip: return "zip";
    case VdbCompression::ActiveMask: return "mask";
    case VdbCompression::None: return "none";
    }
    return "?";
}

VdbCompression parseVdbCompression(const std::string& name) {
    for (VdbCompression c : {VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::ActiveMask, VdbCompression::None})
        if (name == toString(c)) return c;
    throw Error("unknown .vdb compression '" + name + "': expected blosc, zip, mask or none");
}

const char* toString(VdbPrecision p) { return p == VdbPrecision::Half ? "half" : "float"; }

VdbPrecision parseVdbPrecision(const std::string& name) {
    if (name == "float") return VdbPrecision::Float;
    if (name == "half") return VdbPrecision::Half;
    throw Error("unknown --precision '" + name + "': expected float or half");
}

std::uint32_t archiveFlags(VdbCompression c) {
    switch (c) {
    case VdbCompression::Blosc: return openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::Zip: return openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::ActiveMask: return openvdb::io::COMPRESS_ACTIVE_MASK;
    case VdbCompression::None: return openvdb::io::COMPRESS_NONE;
    }
    return openvdb::io::COMPRESS_NONE;
}

bool streamLeavesFromEnvironment() {
    return countFromEnvironment("YV_STREAM_LEAVES", 0, 1, "switches (0: off, 1: on)").value_or(1) == 1;
}

} // namespace yv
