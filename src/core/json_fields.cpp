#include "core/json_fields.h"

#include "core/error.h"

#include <charconv>
#include <cmath>

namespace yv {

Json parseJson(const std::string& text, const std::string& where) {
    try {
        return Json::parse(text);
    } catch (const Json::exception& e) { // a syntax error, or a number beyond a double's range
        throw Error(where + ": not JSON (" + e.what() + ")");
    }
}

std::string jsonText(const Json& value, int indent) {
    return value.dump(indent, ' ', false, Json::error_handler_t::replace);
}

JsonFields::JsonFields(const Json& object, std::string where) : object_(object), where_(std::move(where)) {
    if (!object_.is_object()) throw Error(where_ + ": expected a JSON object, found " + jsonText(object_, -1));
}

void JsonFields::onlyKeys(std::initializer_list<const char*> known) const {
    for (const auto& [key, value] : object_.items()) {
        bool found = false;
        for (const char* k : known) found = found || key == k;
        if (!found) fail(key, "no such field");
    }
}

void JsonFields::fail(const std::string& key, const std::string& what) const {
    throw Error(where_ + ": \"" + key + "\": " + what);
}

const Json& JsonFields::at(const char* key) const {
    const auto it = object_.find(key);
    if (it == object_.end()) fail(key, "missing");
    return *it;
}

std::string JsonFields::string(const char* key) const {
    const Json& v = at(key);
    if (!v.is_string()) fail(key, "expected a string, found " + jsonText(v, -1));
    return v.get<std::string>();
}

double JsonFields::numberOf(const Json& v, const char* key) const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(key, "expected a finite number, found " + jsonText(v, -1));
    return v.get<double>();
}

std::int64_t JsonFields::integerOf(const Json& v, const char* key, std::int64_t min, std::int64_t max) const {
    const bool fits = v.is_number_unsigned() ? max >= 0 && v.get<std::uint64_t>() <= std::uint64_t(max)
                                             : v.is_number_integer();
    if (!fits || v.get<std::int64_t>() < min || v.get<std::int64_t>() > max)
        fail(key, "expected an integer from " + std::to_string(min) + " to " + std::to_string(max) + ", found " +
                      jsonText(v, -1));
    return v.get<std::int64_t>();
}

const Json& JsonFields::arrayOf(const char* key, std::size_t count) const {
    const Json& a = at(key);
    if (!a.is_array() || a.size() != count)
        fail(key, "expected an array of " + std::to_string(count) + " numbers, found " + jsonText(a, -1));
    return a;
}

double JsonFields::number(const char* key) const { return numberOf(at(key), key); }

std::int64_t JsonFields::integer(const char* key, std::int64_t min, std::int64_t max) const {
    return integerOf(at(key), key, min, max);
}

std::vector<double> JsonFields::numbers(const char* key, std::size_t count) const {
    std::vector<double> out;
    for (const Json& v : arrayOf(key, count)) out.push_back(numberOf(v, key));
    return out;
}

std::vector<std::int64_t> JsonFields::integers(const char* key, std::size_t count, std::int64_t min,
                                               std::int64_t max) const {
    std::vector<std::int64_t> out;
    for (const Json& v : arrayOf(key, count)) out.push_back(integerOf(v, key, min, max));
    return out;
}

std::uint64_t JsonFields::unsignedInteger(const char* key) const {
    const Json& v = at(key);
    if (!v.is_number_unsigned()) fail(key, "expected an integer not below 0, found " + jsonText(v, -1));
    return v.get<std::uint64_t>();
}

bool JsonFields::boolean(const char* key) const {
    const Json& v = at(key);
    if (!v.is_boolean()) fail(key, "expected true or false, found " + jsonText(v, -1));
    return v.get<bool>();
}

std::uint64_t JsonFields::hex(const char* key) const {
    const std::string s = string(key);
    std::uint64_t value = 0;
    const char* end = s.data() + s.size();
    const auto [ptr, ec] = s.size() == 18 && s.starts_with("0x") ? std::from_chars(s.data() + 2, end, value, 16)
                                                                 : std::from_chars_result{s.data(), std::errc::invalid_argument};
    if (ec != std::errc() || ptr != end) fail(key, "expected \"0x\" and 16 hex digits, found \"" + s + "\"");
    return value;
}

} // namespace yv
