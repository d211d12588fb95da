// Strict reads of JSON that yarnvox wrote (a work dir's manifest, stage
// times): each value of the type and range the writer gives it, or a
// yv::Error naming the file and the field, never a silent default.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace yv {

using Json = nlohmann::ordered_json;

/// `text` parsed; throws yv::Error "WHERE: not JSON (...)" otherwise.
Json parseJson(const std::string& text, const std::string& where);

/// The JSON text of `value`, two spaces an indent level (-1: one line);
/// bytes that are not UTF-8 become U+FFFD.
std::string jsonText(const Json& value, int indent = 2);

/// Reads the fields of one JSON object; `where` names it in errors
/// ("m/manifest", "m/manifest: run").
class JsonFields {
  public:
    /// Throws unless `object` is an object.
    JsonFields(const Json& object, std::string where);

    /// Throws when the object has a key not in `known`.
    void onlyKeys(std::initializer_list<const char*> known) const;
    bool has(const char* key) const { return object_.contains(key); }

    /// The value of `key`, which must be there.
    const Json& at(const char* key) const;
    std::string string(const char* key) const;
    /// A finite number.
    double number(const char* key) const;
    /// An integer in [min, max].
    std::int64_t integer(const char* key, std::int64_t min, std::int64_t max) const;
    std::uint64_t unsignedInteger(const char* key) const;
    bool boolean(const char* key) const;
    /// An array of `count` finite numbers.
    std::vector<double> numbers(const char* key, std::size_t count) const;
    /// An array of `count` integers in [min, max].
    std::vector<std::int64_t> integers(const char* key, std::size_t count, std::int64_t min, std::int64_t max) const;
    /// "0x" and 16 hex digits (hex64), for 64-bit hashes.
    std::uint64_t hex(const char* key) const;

    /// Throws yv::Error "WHERE: "KEY": expected WHAT".
    [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  private:
    double numberOf(const Json& v, const char* key) const;
    std::int64_t integerOf(const Json& v, const char* key, std::int64_t min, std::int64_t max) const;
    const Json& arrayOf(const char* key, std::size_t count) const;

    const Json& object_;
    std::string where_;
};

} // namespace yv
