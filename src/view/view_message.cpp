#include "view/view_message.h"

#include "core/error.h"
#include "core/text.h"
#include "inspect/transfer_function.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <optional>

namespace yv {
namespace {

using Json = nlohmann::json;

/// The largest integer a double (and so the page's JavaScript) holds exactly.
constexpr double kMaxExactInteger = 9007199254740992.0;

/// A limit as a message shows it: "16", "0.01", "9.0072e+15".
std::string limitText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.5g", v);
    return text;
}

void requireOnlyFields(const Json& object, std::initializer_list<const char*> allowed, const std::string& type) {
    for (const auto& [key, value] : object.items()) {
        bool known = false;
        for (const char* name : allowed) known = known || key == name;
        if (!known) throw Error("a '" + type + "' message has no field '" + shownName(key) + "'");
    }
}

double number(const Json& object, const char* field, double lo, double hi, const std::string& type) {
    const auto it = object.find(field);
    if (it == object.end()) throw Error("a '" + type + "' message needs the field '" + field + "'");
    if (!it->is_number()) throw Error("'" + std::string(field) + "' of a '" + type + "' message must be a number");
    const double v = it->get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
        throw Error("'" + std::string(field) + "' of a '" + type + "' message must lie in [" + limitText(lo) + ", " +
                    limitText(hi) + "]");
    return v;
}

double integer(const Json& object, const char* field, double lo, double hi, const std::string& type) {
    const double v = number(object, field, lo, hi, type);
    if (v != std::floor(v)) throw Error("'" + std::string(field) + "' of a '" + type + "' message must be a whole number");
    return v;
}

/// A true-or-false field; `fallback` where it may be left out (else it must be there).
bool boolean(const Json& object, const char* field, const std::string& type, std::optional<bool> fallback = std::nullopt) {
    const auto it = object.find(field);
    if (it == object.end()) {
        if (fallback) return *fallback;
        throw Error("a '" + type + "' message needs '" + field + "', true or false");
    }
    if (!it->is_boolean()) throw Error("a '" + type + "' message's '" + field + "' must be true or false");
    return it->get<bool>();
}

CameraMessage parseCamera(const Json& m) {
    const std::string type = "camera";
    requireOnlyFields(m, {"type", "azimuth", "elevation", "distance", "panX", "panY", "seq", "moving"}, type);
    CameraMessage c;
    // The page keeps the azimuth within a turn or two; a wider range is a runaway client.
    c.camera.azimuth = number(m, "azimuth", -3600.0, 3600.0, type);
    c.camera.elevation = number(m, "elevation", -90.0, 90.0, type);
    c.camera.distance = number(m, "distance", 0.01, 1000.0, type);
    c.camera.panX = number(m, "panX", -100.0, 100.0, type);
    c.camera.panY = number(m, "panY", -100.0, 100.0, type);
    c.camera.seq = std::uint64_t(integer(m, "seq", 0.0, kMaxExactInteger, type));
    c.moving = boolean(m, "moving", type, false);
    return c;
}

/// A name field (a mode, a preset): 1 to 32 of a-z and '-'.
std::string name(const Json& m, const char* field, const std::string& type) {
    const auto it = m.find(field);
    if (it == m.end() || !it->is_string())
        throw Error("a '" + type + "' message needs the string field '" + field + "'");
    const std::string& text = it->get_ref<const std::string&>();
    if (text.empty() || text.size() > 32)
        throw Error("a '" + type + "' message's " + field + " must be 1 to 32 characters");
    for (char ch : text)
        if (!((ch >= 'a' && ch <= 'z') || ch == '-'))
            throw Error("a '" + type + "' message's " + field + " may hold only a-z and '-'");
    return text;
}

ModeMessage parseMode(const Json& m) {
    requireOnlyFields(m, {"type", "mode"}, "mode");
    return ModeMessage{name(m, "mode", "mode")};
}

TransferMessage parseTransfer(const Json& m) {
    const std::string type = "transfer";
    requireOnlyFields(m, {"type", "preset", "opacity"}, type);
    TransferMessage t;
    t.preset = name(m, "preset", type);
    t.opacity = number(m, "opacity", kMinOpacityScale, kMaxOpacityScale, type);
    return t;
}

SizeMessage parseSize(const Json& m, const std::string& type) {
    requireOnlyFields(m, {"type", "width", "height"}, type);
    SizeMessage s;
    s.width = int(integer(m, "width", kMinViewSide, kMaxViewSide, type));
    s.height = int(integer(m, "height", kMinViewSide, kMaxViewSide, type));
    return s;
}

} // namespace

ViewMessage parseViewMessage(std::string_view text) {
    if (text.size() > kMaxViewMessageBytes)
        throw Error("a message of " + std::to_string(text.size()) + " bytes (at most " +
                    std::to_string(kMaxViewMessageBytes) + ")");
    // No exceptions from the parser: a bad byte is a refusal, not a stack unwinding through it.
    const Json m = Json::parse(text.begin(), text.end(), nullptr, false);
    if (m.is_discarded()) throw Error("a message that is not JSON");
    if (!m.is_object()) throw Error("a message that is not a JSON object");
    const auto type = m.find("type");
    if (type == m.end() || !type->is_string()) throw Error("a message without a string 'type'");
    const std::string& t = type->get_ref<const std::string&>();
    if (t == "camera") return parseCamera(m);
    if (t == "mode") return parseMode(m);
    if (t == "size") return parseSize(m, t);
    if (t == "transfer") return parseTransfer(m);
    if (t == "twist") {
        requireOnlyFields(m, {"type", "twist"}, t);
        return TwistMessage{number(m, "twist", -kMaxViewTwist, kMaxViewTwist, t)};
    }
    if (t == "screenshot") {
        const SizeMessage s = parseSize(m, t);
        return ScreenshotMessage{s.width, s.height};
    }
    if (t == "voxelize-view") {
        requireOnlyFields(m, {"type"}, t);
        return VoxelizeViewMessage{};
    }
    if (t == "layout") {
        requireOnlyFields(m, {"type", "blend"}, t);
        return LayoutMessage{boolean(m, "blend", t)};
    }
    if (t == "quality") {
        requireOnlyFields(m, {"type", "degrade"}, t);
        return QualityMessage{boolean(m, "degrade", t)};
    }
    if (t == "save-view") {
        requireOnlyFields(m, {"type", "workDir"}, t);
        return SaveViewMessage{boolean(m, "workDir", t, false)};
    }
    throw Error("a message of unknown type '" + shownName(t) +
                "' (known: camera, mode, size, layout, quality, transfer, twist, voxelize-view, save-view, screenshot)");
}

std::string formatViewMessage(const ViewMessage& message) {
    Json j;
    if (const auto* c = std::get_if<CameraMessage>(&message)) {
        j = {{"type", "camera"},
             {"azimuth", c->camera.azimuth},
             {"elevation", c->camera.elevation},
             {"distance", c->camera.distance},
             {"panX", c->camera.panX},
             {"panY", c->camera.panY},
             {"seq", c->camera.seq},
             {"moving", c->moving}};
    } else if (const auto* m = std::get_if<ModeMessage>(&message)) {
        j = {{"type", "mode"}, {"mode", m->mode}};
    } else if (const auto* s = std::get_if<SizeMessage>(&message)) {
        j = {{"type", "size"}, {"width", s->width}, {"height", s->height}};
    } else if (const auto* layout = std::get_if<LayoutMessage>(&message)) {
        j = {{"type", "layout"}, {"blend", layout->blend}};
    } else if (const auto* quality = std::get_if<QualityMessage>(&message)) {
        j = {{"type", "quality"}, {"degrade", quality->degrade}};
    } else if (const auto* shot = std::get_if<ScreenshotMessage>(&message)) {
        j = {{"type", "screenshot"}, {"width", shot->width}, {"height", shot->height}};
    } else if (const auto* transfer = std::get_if<TransferMessage>(&message)) {
        j = {{"type", "transfer"}, {"preset", transfer->preset}, {"opacity", transfer->opacity}};
    } else if (const auto* twist = std::get_if<TwistMessage>(&message)) {
        j = {{"type", "twist"}, {"twist", twist->twist}};
    } else if (const auto* save = std::get_if<SaveViewMessage>(&message)) {
        j = {{"type", "save-view"}, {"workDir", save->workDir}};
    } else {
        j = {{"type", "voxelize-view"}};
    }
    return j.dump();
}

} // namespace yv
