// Run statistics, written as JSON by --stats and read by the benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace yv {

/// An ordered JSON object of numbers, strings, nested objects and arrays of
/// objects. Setting a number or string under a key already there replaces
/// its value in place.
class JsonObject {
  public:
    JsonObject& set(const std::string& key, double value);
    JsonObject& set(const std::string& key, std::int64_t value);
    JsonObject& set(const std::string& key, std::uint64_t value) { return set(key, static_cast<std::int64_t>(value)); }
    JsonObject& set(const std::string& key, int value) { return set(key, static_cast<std::int64_t>(value)); }
    JsonObject& set(const std::string& key, const std::string& value);
    JsonObject& set(const std::string& key, const char* value) { return set(key, std::string(value)); }
    JsonObject& set(const std::string& key, bool value);
    JsonObject& set(const std::string& key, const JsonObject& value);
    JsonObject& set(const std::string& key, const std::vector<JsonObject>& values);
    std::string dump(int indent = 0) const;

  private:
    /// A number or string under `key`: replaces the value of a key already there, in place.
    void put(const std::string& key, std::string encoded);
    std::vector<std::pair<std::string, std::string>> fields_; // key, encoded value
    std::vector<JsonObject> nested_;
    std::vector<std::vector<JsonObject>> arrays_;
};

std::string jsonQuote(const std::string& s);

/// Writes text to `path` through a temporary file and a rename.
void writeTextFileAtomically(const std::string& path, const std::string& text);

} // namespace yv
