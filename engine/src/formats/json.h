// run.json through nlohmann-json: the recorder builds an ordered_json and dumps it with
// dump_json; readers parse with JsonDocument, which remembers the line each value starts on so
// that errors name FILE:LINE.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

#include <nlohmann/json.hpp>

namespace gaitlab::formats {

/// `v` as run.json text: two-space indent, arrays of scalars on one line, members in their
/// order, doubles in their shortest form that reads back to the same bits, NaN and infinities
/// as null, bytes that are not well-formed UTF-8 as U+FFFD; ends with a line end.
std::string dump_json(const nlohmann::ordered_json& v);

/// A parsed JSON text that knows the line each of its values starts on. Duplicate member names
/// keep the first value. Not copyable or movable: lines are kept by the values' addresses.
class JsonDocument {
  public:
    /// Parses `text`; `file` names it in errors ("FILE:LINE: message"); throws FormatError.
    JsonDocument(std::string_view text, std::string file);
    JsonDocument(const JsonDocument&) = delete;
    JsonDocument& operator=(const JsonDocument&) = delete;

    const nlohmann::json& root() const { return root_; }
    const std::string& file() const { return file_; }
    /// The line `v`, a value of this document, starts on (0 for a value from elsewhere).
    int line(const nlohmann::json& v) const;

  private:
    friend class JsonBuilder;
    std::string file_;
    nlohmann::json root_;
    std::unordered_map<const nlohmann::json*, int> lines_;
};

/// Member `key` of object `o`, or nullptr (also when `o` is not an object).
const nlohmann::json* find(const nlohmann::json& o, std::string_view key);
/// Member `key` as a string: "" when it is missing or not a string.
std::string str_at(const nlohmann::json& o, std::string_view key);
/// `v` as a string, or `fallback` when it is not one.
std::string as_string(const nlohmann::json& v, const std::string& fallback = "");
/// `v` as a whole number (1e3 is one; 0.5, 1e300 and non-numbers are not).
std::optional<long long> as_integer(const nlohmann::json& v);
/// `v` as an unsigned 64-bit integer written as one, or `fallback`.
std::uint64_t as_uint(const nlohmann::json& v, std::uint64_t fallback = 0);

}  // namespace gaitlab::formats
