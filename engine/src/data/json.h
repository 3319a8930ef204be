// A small JSON value for the run folder's run.json: built and dumped by the recorder, parsed by
// the reader (errors name FILE:LINE). Object members keep their order.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gaitlab::data {

class Json {
  public:
    enum class Type { null, boolean, number, string, array, object };

    Json() = default;
    Json(bool b) : type_(Type::boolean), bool_(b) {}                   // NOLINT: implicit by design
    Json(double v);                                                    // NOLINT
    Json(int v) : Json(static_cast<long long>(v)) {}                   // NOLINT
    Json(long v) : Json(static_cast<long long>(v)) {}                  // NOLINT
    Json(long long v);                                                 // NOLINT
    Json(std::uint64_t v);                                             // NOLINT
    Json(const char* s) : type_(Type::string), text_(s) {}             // NOLINT
    Json(std::string s) : type_(Type::string), text_(std::move(s)) {}  // NOLINT
    /// A number keeping the text it was parsed from (integers read back exactly).
    static Json raw_number(double v, std::string text) {
        Json j(Type::number);
        j.number_ = v;
        j.text_ = std::move(text);
        return j;
    }
    static Json array() { return Json(Type::array); }
    static Json object() { return Json(Type::object); }

    Type type() const { return type_; }
    /// The line the value starts on in the text it was parsed from (0: not parsed).
    int line() const { return line_; }
    void set_line(int line) { line_ = line; }
    bool is_null() const { return type_ == Type::null; }

    /// Appends to an array.
    Json& push(Json v);
    /// Sets an object member (replacing one of the same name).
    Json& set(const std::string& key, Json v);
    /// Appends an object member without looking for one of the same name (find() gives the
    /// first): what the parser does, in constant time.
    Json& add(std::string key, Json v);
    /// An object member or nullptr.
    const Json* find(std::string_view key) const;
    const std::vector<Json>& items() const { return items_; }
    const std::vector<std::pair<std::string, Json>>& members() const { return members_; }

    /// The value as a string, number, integer or boolean, or `fallback` when it is another type.
    std::string str(const std::string& fallback = "") const;
    double num(double fallback = 0) const;
    long long integer(long long fallback = 0) const;
    std::uint64_t uint(std::uint64_t fallback = 0) const;
    bool boolean(bool fallback = false) const;

    /// Member `key` as a string ("" if missing or not a string); likewise for numbers.
    std::string str_at(std::string_view key) const;
    double num_at(std::string_view key, double fallback = 0) const;
    long long int_at(std::string_view key, long long fallback = 0) const;

    /// Pretty-printed text (two-space indent), ending with a line end.
    std::string dump() const;

    /// Parses `text`; `file` names it in errors ("FILE:LINE: message"); throws FormatError.
    static Json parse(std::string_view text, const std::string& file);

  private:
    explicit Json(Type t) : type_(t) {}
    void dump(std::string& out, int indent) const;

    Type type_ = Type::null;
    int line_ = 0;
    bool bool_ = false;
    double number_ = 0;
    std::string text_;  // string value, or the number as written
    std::vector<Json> items_;
    std::vector<std::pair<std::string, Json>> members_;
};

}  // namespace gaitlab::data
