#include "formats/json.h"

#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "gaitlab/error.h"

namespace gaitlab::formats {

using nlohmann::json;
using nlohmann::ordered_json;

namespace {

// a scalar or a member name as JSON text: nlohmann escapes it and writes every byte that is
// not part of well-formed UTF-8 (a name made of arbitrary bytes) as U+FFFD, so the file is
// always valid JSON
void dump_scalar(std::string& out, const ordered_json& v) {
    if (v.is_number_float()) {
        // fmt's shortest form reads back to the same bits; "-0" would read back as the
        // integer 0, so negative zero keeps its point
        const double d = v.get<double>();
        if (!std::isfinite(d)) {
            out += "null";  // JSON has no NaN or infinity
        } else if (d == 0 && std::signbit(d)) {
            out += "-0.0";
        } else {
            out += fmt::format("{}", d);
        }
        return;
    }
    out += v.dump(-1, ' ', false, json::error_handler_t::replace);
}

void dump_value(std::string& out, const ordered_json& v, int indent) {
    const std::string pad(static_cast<size_t>(indent + 2), ' ');
    if (v.is_array()) {
        if (v.empty()) {
            out += "[]";
            return;
        }
        // arrays of scalars stay on one line
        bool flat = true;
        for (const ordered_json& item : v)
            flat = flat && !item.is_structured();
        out += "[";
        bool first = true;
        for (const ordered_json& item : v) {
            if (!first) out += flat ? ", " : ",";
            first = false;
            if (!flat) out += "\n" + pad;
            dump_value(out, item, indent + 2);
        }
        if (!flat) out += "\n" + std::string(static_cast<size_t>(indent), ' ');
        out += "]";
    } else if (v.is_object()) {
        if (v.empty()) {
            out += "{}";
            return;
        }
        out += "{";
        bool first = true;
        for (const auto& [key, value] : v.items()) {
            if (!first) out += ",";
            first = false;
            out += "\n" + pad;
            dump_scalar(out, ordered_json(key));
            out += ": ";
            dump_value(out, value, indent + 2);
        }
        out += "\n" + std::string(static_cast<size_t>(indent), ' ') + "}";
    } else {
        dump_scalar(out, v);
    }
}

// an input iterator over the text that records how far nlohmann's lexer has read, so the
// builder knows the line of each value it is handed
class Cursor {
  public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    Cursor(const char* p, const char** reached) : p_(p), reached_(reached) {}
    reference operator*() const { return *p_; }
    Cursor& operator++() {
        *reached_ = ++p_;
        return *this;
    }
    Cursor operator++(int) {
        Cursor before = *this;
        ++*this;
        return before;
    }
    bool operator==(const Cursor& o) const { return p_ == o.p_; }
    bool operator!=(const Cursor& o) const { return p_ != o.p_; }

  private:
    const char* p_;
    const char** reached_;
};

// "'x'" for a printable byte, "byte 0x1b" for another
std::string describe_byte(unsigned char c) {
    return c > 0x20 && c < 0x7f ? fmt::format("'{}'", static_cast<char>(c))
                                : fmt::format("byte 0x{:02x}", c);
}

// nlohmann's text with every byte that is not printable ASCII written as \xNN
std::string printable(std::string_view s) {
    std::string out;
    for (const char c : s) {
        const auto b = static_cast<unsigned char>(c);
        out += b >= 0x20 && b < 0x7f ? std::string(1, c) : fmt::format("\\x{:02x}", b);
    }
    return out;
}

bool starts_with(std::string_view s, std::string_view prefix) {
    return s.substr(0, prefix.size()) == prefix;
}

}  // namespace

// builds the document from nlohmann's SAX events, noting the line of each value
class JsonBuilder {
  public:
    JsonBuilder(JsonDocument& doc, std::string_view text, const char* const& reached)
        : doc_(doc), text_(text), reached_(reached) {}

    bool null() { return scalar(json(nullptr)); }
    bool boolean(bool b) { return scalar(json(b)); }
    bool number_integer(json::number_integer_t v) { return scalar(json(v)); }
    bool number_unsigned(json::number_unsigned_t v) { return scalar(json(v)); }
    bool number_float(json::number_float_t v, const std::string& /*text*/) {
        return scalar(json(v));
    }
    bool string(std::string& s) { return scalar(json(std::move(s))); }
    bool binary(json::binary_t& /*b*/) { return true; }  // JSON text has none
    bool start_object(std::size_t /*size*/) { return open(json::value_t::object); }
    bool start_array(std::size_t /*size*/) { return open(json::value_t::array); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }

    bool key(std::string& k) {
        if (skipping_ > 0) return true;
        auto& members = stack_.back().value->get_ref<json::object_t&>();
        const auto [it, fresh] = members.emplace(std::move(k), nullptr);
        if (fresh) {
            member_ = &it->second;
        } else {
            skip_value_ = true;  // a second member of the same name: the first one counts
        }
        return true;
    }

    bool parse_error(std::size_t position, const std::string& /*last_token*/,
                     const nlohmann::detail::exception& ex) {
        // `position` counts the bytes read, the offending one (or the end of the text) last
        const size_t end = std::min(position > 0 ? position - 1 : 0, text_.size());
        int line = 1;
        for (size_t k = 0; k < end; ++k)
            line += text_[k] == '\n';
        fail(line, message(ex.what(), end));
    }

  private:
    struct Frame {
        json* value;
        std::vector<int> item_lines;  // an array's items move as it grows: their lines wait here
    };

    [[noreturn]] void fail(int line, const std::string& what) const {
        throw FormatError(fmt::format("{}:{}: {}", doc_.file_, line, what), doc_.file_, line);
    }

    // the line of the token nlohmann has just read: its last byte is the one before the
    // lexer's position, or one more before after a number (whose end the lexer reads past)
    int line_now() {
        const size_t end = static_cast<size_t>(reached_ - text_.data()) - 1;
        for (; scanned_ < end; ++scanned_)
            line_ += text_[scanned_] == '\n';
        return line_;
    }

    json* place(json v) {
        const int line = line_now();
        if (stack_.empty()) {
            doc_.root_ = std::move(v);
            doc_.lines_[&doc_.root_] = line;
            return &doc_.root_;
        }
        Frame& f = stack_.back();
        if (f.value->is_array()) {
            auto& items = f.value->get_ref<json::array_t&>();
            items.push_back(std::move(v));
            f.item_lines.push_back(line);
            return &items.back();
        }
        *member_ = std::move(v);
        doc_.lines_[member_] = line;
        return member_;
    }

    bool scalar(json v) {
        if (skipping_ > 0) return true;
        if (skip_value_) {
            skip_value_ = false;
            return true;
        }
        place(std::move(v));
        return true;
    }

    bool open(json::value_t type) {
        if (stack_.size() + static_cast<size_t>(skipping_) >= kMaxDepth) {
            fail(line_now(), "JSON nested too deeply");
        }
        if (skipping_ > 0 || skip_value_) {
            skip_value_ = false;
            ++skipping_;
            return true;
        }
        json* v = place(json(type));
        stack_.push_back(Frame{v, {}});
        return true;
    }

    bool close() {
        if (skipping_ > 0) {
            --skipping_;
            return true;
        }
        Frame& f = stack_.back();
        if (f.value->is_array()) {
            const auto& items = f.value->get_ref<const json::array_t&>();
            for (size_t i = 0; i < items.size(); ++i)
                doc_.lines_[&items[i]] = f.item_lines[i];
        }
        stack_.pop_back();
        return true;
    }

    // nlohmann's message in gaitlab's words: where it expected what. `at` is the offset of the
    // offending byte (the text's size at its end).
    std::string message(std::string_view what, size_t at) const {
        // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error while
        // parsing value - invalid literal; last read: 'x'; expected ..."
        if (const size_t p = what.find("] "); p != std::string_view::npos)
            what.remove_prefix(p + 2);
        if (starts_with(what, "parse error")) {
            if (const size_t p = what.find(": "); p != std::string_view::npos) {
                what.remove_prefix(p + 2);
            }
        }
        std::string_view context;
        std::string_view detail = what;
        if (starts_with(what, "syntax error while parsing ")) {
            const std::string_view rest = what.substr(27);
            const size_t dash = rest.find(" - ");
            if (dash != std::string_view::npos) {
                context = rest.substr(0, dash);
                detail = rest.substr(dash + 3);
            }
        }
        const bool unexpected = starts_with(detail, "unexpected ");
        if (!unexpected) detail = detail.substr(0, detail.find("; last read: "));

        if (starts_with(detail, "invalid string: missing closing quote")) {
            return "unterminated string";
        }
        if (starts_with(detail, "invalid string: forbidden character after backslash")) {
            if (at >= text_.size()) return "unterminated string";
            const auto c = static_cast<unsigned char>(text_[at]);
            return c > 0x20 && c < 0x7f
                       ? fmt::format("unknown escape '\\{}' in a string", static_cast<char>(c))
                       : fmt::format("unknown escape: '\\' and byte 0x{:02x} in a string", c);
        }
        if (starts_with(detail, "invalid string: '\\u' must be followed by 4 hex digits")) {
            return "four hex digits expected after \\u";
        }
        if (starts_with(detail, "invalid string") || starts_with(detail, "invalid number") ||
            starts_with(detail, "number overflow") || starts_with(detail, "invalid BOM")) {
            return printable(detail);
        }
        if (context == "value") {
            if (what.size() >= 23 && what.substr(what.size() - 23) == "; expected end of input") {
                return "end of file expected after the JSON value";
            }
            if (at >= text_.size()) return "JSON value expected, got the end of the file";
            // the byte the value should start with: a literal cut short ("tru]") names its
            // first letter
            size_t start = at;
            for (size_t k = 1; k <= 4 && k <= at && detail == "invalid literal"; ++k) {
                const std::string_view w = text_.substr(at - k, k);
                if (starts_with("true", w) || starts_with("false", w) || starts_with("null", w)) {
                    start = at - k;
                }
            }
            const auto c = static_cast<unsigned char>(text_[start]);
            return "JSON value expected, got " + describe_byte(c);
        }
        if (context == "object key") return "member name (a string) expected";
        if (context == "object separator") return "':' expected after a member name";
        if (context == "object") return "',' or '}' expected in an object";
        if (context == "array") return "',' or ']' expected in an array";
        return printable(what);
    }

    static constexpr size_t kMaxDepth = 65;

    JsonDocument& doc_;
    std::string_view text_;
    const char* const& reached_;
    std::vector<Frame> stack_;
    json* member_ = nullptr;
    bool skip_value_ = false;
    int skipping_ = 0;
    size_t scanned_ = 0;
    int line_ = 1;
};

std::string dump_json(const ordered_json& v) {
    std::string out;
    dump_value(out, v, 0);
    out += "\n";
    return out;
}

JsonDocument::JsonDocument(std::string_view text, std::string file) : file_(std::move(file)) {
    const char* reached = text.data();
    JsonBuilder builder(*this, text, reached);
    json::sax_parse(Cursor(text.data(), &reached), Cursor(text.data() + text.size(), &reached),
                    &builder);
}

int JsonDocument::line(const json& v) const {
    const auto it = lines_.find(&v);
    return it == lines_.end() ? 0 : it->second;
}

const json* find(const json& o, std::string_view key) {
    if (!o.is_object()) return nullptr;
    const auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
}

std::string str_at(const json& o, std::string_view key) {
    const json* v = find(o, key);
    return v ? as_string(*v) : "";
}

std::string as_string(const json& v, const std::string& fallback) {
    return v.is_string() ? v.get_ref<const std::string&>() : fallback;
}

std::optional<long long> as_integer(const json& v) {
    if (v.is_number_integer() && !v.is_number_unsigned()) return v.get<long long>();
    if (v.is_number_unsigned()) {
        const auto u = v.get<std::uint64_t>();
        if (u <= static_cast<std::uint64_t>(std::numeric_limits<long long>::max()))
            return static_cast<long long>(u);
        return std::nullopt;
    }
    if (v.is_number_float()) {
        // 1e3 is an integer too; 1e300 and 0.5 are not
        const double d = v.get<double>();
        if (d >= -9.2e18 && d <= 9.2e18 && d == std::trunc(d)) return static_cast<long long>(d);
    }
    return std::nullopt;
}

std::uint64_t as_uint(const json& v, std::uint64_t fallback) {
    if (v.is_number_unsigned()) return v.get<std::uint64_t>();
    return fallback;
}

}  // namespace gaitlab::formats
