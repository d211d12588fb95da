// libFuzzer target: the colour map reader of `inspect --tf FILE`
// (src/inspect/transfer_function.cpp).
#include "core/error.h"
#include "inspect/transfer_function.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const yv::TransferFunction tf = yv::parseColourMap(std::string(data, data + size), "fuzz/colour-map");
        // What parses is a table of colours and opacities in [0, 1].
        for (const auto& e : tf)
            for (int c = 0; c < 4; ++c)
                if (!(e[c] >= 0.0f && e[c] <= 1.0f)) __builtin_trap();
    } catch (const yv::Error&) {
    }
    return 0;
}
