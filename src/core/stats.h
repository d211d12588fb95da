// Run statistics, written as JSON by --stats and read by the benchmarks.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace yv {

/// An ordered JSON object of numbers, strings, nested objects and arrays of
/// objects, over nlohmann::ordered_json: keys keep the order they were first
/// set in, and setting a key again replaces its value where it stands.
class JsonObject {
  public:
    JsonObject();
    JsonObject(const JsonObject& other);
    JsonObject(JsonObject&&) noexcept;
    JsonObject& operator=(const JsonObject& other);
    JsonObject& operator=(JsonObject&&) noexcept;
    ~JsonObject();

    /// A double keeps 9 significant digits (what --stats has always carried);
    /// NaN and infinities are null.
    JsonObject& set(const std::string& key, double value);
    JsonObject& set(const std::string& key, std::int64_t value);
    JsonObject& set(const std::string& key, std::uint64_t value) { return set(key, static_cast<std::int64_t>(value)); }
    JsonObject& set(const std::string& key, int value) { return set(key, static_cast<std::int64_t>(value)); }
    JsonObject& set(const std::string& key, const std::string& value);
    JsonObject& set(const std::string& key, const char* value) { return set(key, std::string(value)); }
    JsonObject& set(const std::string& key, bool value);
    JsonObject& set(const std::string& key, const JsonObject& value);
    JsonObject& set(const std::string& key, const std::vector<JsonObject>& values);
    /// The object as JSON text, two spaces an indent level; bytes that are
    /// not UTF-8 become U+FFFD.
    std::string dump() const;

  private:
    std::unique_ptr<nlohmann::ordered_json> json_;
};

/// `s` as a JSON string, quotes included.
std::string jsonQuote(const std::string& s);

/// Writes text to `path` through a temporary file and a rename (core/atomic_file.h).
void writeTextFileAtomically(const std::string& path, const std::string& text);

} // namespace yv
