// libFuzzer target: the parser of `yarnvox view`'s page messages (src/view/view_message.cpp).
#include "core/error.h"
#include "view/view_message.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const yv::ViewMessage m = yv::parseViewMessage(std::string_view(reinterpret_cast<const char*>(data), size));
        // What parses is within the limits, and formats and parses back to the same message.
        if (const auto* c = std::get_if<yv::CameraMessage>(&m))
            if (!std::isfinite(c->camera.azimuth) || !(c->camera.distance > 0.0) || std::abs(c->camera.elevation) > 90.0)
                __builtin_trap();
        if (const auto* s = std::get_if<yv::SizeMessage>(&m))
            if (s->width < yv::kMinViewSide || s->width > yv::kMaxViewSide || s->height < yv::kMinViewSide ||
                s->height > yv::kMaxViewSide)
                __builtin_trap();
        if (yv::formatViewMessage(yv::parseViewMessage(yv::formatViewMessage(m))) != yv::formatViewMessage(m))
            __builtin_trap();
    } catch (const yv::Error&) {
    }
    return 0;
}
