// libFuzzer target: the work dir's manifest parser (src/store/manifest.cpp).
#include "core/error.h"
#include "store/manifest.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const yv::StoreManifest m = yv::parseManifest("fuzz/manifest", std::string(data, data + size));
        // What parses must format and parse back to the same run.
        const yv::StoreManifest back = yv::parseManifest("fuzz/manifest-again", yv::formatManifest(m));
        if (!yv::runDifference(m, back).empty() || yv::metadataFields(back.run) != yv::metadataFields(m.run) ||
            back.stageSeconds != m.stageSeconds) __builtin_trap();
    } catch (const yv::Error&) {
    }
    return 0;
}
