#include "core/stats.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace yv {

std::string jsonQuote(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        switch (ch) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        default:
            if (static_cast<unsigned char>(ch) < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", ch);
                out += buf;
            } else {
                out += ch;
            }
        }
    }
    return out + "\"";
}

void JsonObject::put(const std::string& key, std::string encoded) {
    for (auto& [k, v] : fields_)
        if (k == key && v.front() != '\x01' && v.front() != '\x02') {
            v = std::move(encoded);
            return;
        }
    fields_.emplace_back(key, std::move(encoded));
}

JsonObject& JsonObject::set(const std::string& key, double value) {
    char buf[64];
    if (std::isfinite(value))
        std::snprintf(buf, sizeof buf, "%.9g", value);
    else
        std::snprintf(buf, sizeof buf, "null");
    put(key, buf);
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, std::int64_t value) {
    put(key, std::to_string(value));
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::string& value) {
    put(key, jsonQuote(value));
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, bool value) {
    fields_.emplace_back(key, value ? "true" : "false");
    return *this;
}
JsonObject& JsonObject::set(const std::string& key, const JsonObject& value) {
    fields_.emplace_back(key, "\x01" + value.dump(0)); // marker: nested object, re-indented on dump
    nested_.push_back(value);
    return *this;
}

JsonObject& JsonObject::set(const std::string& key, const std::vector<JsonObject>& values) {
    fields_.emplace_back(key, "\x02"); // marker: array of objects
    arrays_.push_back(values);
    return *this;
}

std::string JsonObject::dump(int indent) const {
    const std::string pad(indent + 2, ' '), end(indent, ' ');
    std::string out = "{\n";
    std::size_t nestedIndex = 0, arrayIndex = 0;
    for (std::size_t i = 0; i < fields_.size(); ++i) {
        const auto& [key, value] = fields_[i];
        out += pad + jsonQuote(key) + ": ";
        if (value.size() && value[0] == '\x01') {
            out += nested_[nestedIndex++].dump(indent + 2);
        } else if (value.size() && value[0] == '\x02') {
            const std::vector<JsonObject>& items = arrays_[arrayIndex++];
            out += "[";
            for (std::size_t k = 0; k < items.size(); ++k)
                out += (k ? ",\n" : "\n") + std::string(indent + 4, ' ') + items[k].dump(indent + 4);
            out += items.empty() ? "]" : "\n" + pad + "]";
        } else {
            out += value;
        }
        out += i + 1 < fields_.size() ? ",\n" : "\n";
    }
    return out + end + "}";
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
    writeFileAtomically(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

} // namespace yv
