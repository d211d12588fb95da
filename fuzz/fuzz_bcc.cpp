// libFuzzer target: the BCC reader (formats/bcc.cpp) on any bytes. A bad file
// must end in yv::Error; anything else (a crash, a sanitizer report, another
// exception) is a bug.
#include "bcc.h"
#include "core/error.h"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const yv::Garment g = yv::parseBcc(std::vector<std::uint8_t>(data, data + size), "fuzz.bcc");
        // What the reader accepts, the writer must encode and read back.
        (void)yv::parseBcc(yv::encodeBcc(g), "fuzz-roundtrip.bcc");
    } catch (const yv::Error&) {
    }
    return 0;
}
