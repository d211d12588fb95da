#include "core/stats.h"

#include "core/atomic_file.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace yv {

JsonObject::JsonObject() : json_(std::make_unique<nlohmann::ordered_json>(nlohmann::ordered_json::object())) {}
JsonObject::JsonObject(const JsonObject& other) : json_(std::make_unique<nlohmann::ordered_json>(*other.json_)) {}
JsonObject::JsonObject(JsonObject&&) noexcept = default;
JsonObject& JsonObject::operator=(const JsonObject& other) {
    *json_ = *other.json_;
    return *this;
}
JsonObject& JsonObject::operator=(JsonObject&&) noexcept = default;
JsonObject::~JsonObject() = default;

JsonObject& JsonObject::set(const std::string& key, double value) {
    if (!std::isfinite(value)) {
        (*json_)[key] = nullptr;
        return *this;
    }
    // Rounded to the 9 digits --stats has always had: readers get the same
    // doubles as before, and a time does not print 17 digits of noise.
    char digits[40];
    std::snprintf(digits, sizeof digits, "%.9g", value);
    (*json_)[key] = std::strtod(digits, nullptr);
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, std::int64_t value) {
    (*json_)[key] = value;
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::string& value) {
    (*json_)[key] = value;
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, bool value) {
    (*json_)[key] = value;
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, const JsonObject& value) {
    (*json_)[key] = *value.json_;
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::vector<JsonObject>& values) {
    nlohmann::ordered_json array = nlohmann::ordered_json::array();
    for (const JsonObject& v : values) array.push_back(*v.json_);
    (*json_)[key] = std::move(array);
    return *this;
}

std::string JsonObject::dump() const { return json_->dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace); }

std::string jsonQuote(const std::string& s) {
    return nlohmann::ordered_json(s).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
    writeFileAtomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

} // namespace yv
