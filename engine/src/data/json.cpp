#include "data/json.h"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/error.h"

namespace gaitlab::data {

Json::Json(double v) : type_(Type::number), number_(v) {
    // JSON has no NaN or infinity: those are written as null
    if (!std::isfinite(v)) {
        type_ = Type::null;
        return;
    }
    text_ = fmt::format("{}", v);
}

Json::Json(long long v)
    : type_(Type::number), number_(static_cast<double>(v)), text_(std::to_string(v)) {}

Json::Json(std::uint64_t v)
    : type_(Type::number), number_(static_cast<double>(v)), text_(std::to_string(v)) {}

Json& Json::push(Json v) {
    items_.push_back(std::move(v));
    return items_.back();
}

Json& Json::set(const std::string& key, Json v) {
    for (auto& m : members_) {
        if (m.first == key) {
            m.second = std::move(v);
            return m.second;
        }
    }
    members_.emplace_back(key, std::move(v));
    return members_.back().second;
}

Json& Json::add(std::string key, Json v) {
    members_.emplace_back(std::move(key), std::move(v));
    return members_.back().second;
}

const Json* Json::find(std::string_view key) const {
    for (const auto& m : members_) {
        if (m.first == key) return &m.second;
    }
    return nullptr;
}

std::string Json::str(const std::string& fallback) const {
    return type_ == Type::string ? text_ : fallback;
}

double Json::num(double fallback) const {
    return type_ == Type::number ? number_ : fallback;
}

long long Json::integer(long long fallback) const {
    if (type_ != Type::number) return fallback;
    long long v = 0;
    const auto r = std::from_chars(text_.data(), text_.data() + text_.size(), v);
    if (r.ec == std::errc() && r.ptr == text_.data() + text_.size()) return v;
    // 1e3 is an integer too; 1e300 and 0.5 are not
    if (number_ >= -9.2e18 && number_ <= 9.2e18 && number_ == std::trunc(number_))
        return static_cast<long long>(number_);
    return fallback;
}

std::uint64_t Json::uint(std::uint64_t fallback) const {
    if (type_ != Type::number) return fallback;
    std::uint64_t v = 0;
    const auto r = std::from_chars(text_.data(), text_.data() + text_.size(), v);
    if (r.ec == std::errc() && r.ptr == text_.data() + text_.size()) return v;
    return fallback;
}

bool Json::boolean(bool fallback) const {
    return type_ == Type::boolean ? bool_ : fallback;
}

std::string Json::str_at(std::string_view key) const {
    const Json* j = find(key);
    return j ? j->str() : "";
}

double Json::num_at(std::string_view key, double fallback) const {
    const Json* j = find(key);
    return j ? j->num(fallback) : fallback;
}

long long Json::int_at(std::string_view key, long long fallback) const {
    const Json* j = find(key);
    return j ? j->integer(fallback) : fallback;
}

namespace {

// the length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlong forms, no
// surrogates, nothing above U+10FFFF), 0 if there is none
size_t utf8_length(const std::string& s, size_t i) {
    const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    if (c < 0x80) return 1;
    size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
    } else {
        return 0;
    }
    if (i + n > s.size()) return 0;
    if (b(i + 1) < lo || b(i + 1) > hi) return 0;
    for (size_t k = 2; k < n; ++k) {
        if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
    }
    return n;
}

// a JSON string: control characters escaped, and every byte that is not part of well-formed
// UTF-8 (a name made of arbitrary bytes) written as U+FFFD, so the file is always valid JSON
void dump_string(std::string& out, const std::string& s) {
    out.push_back('"');
    for (size_t i = 0; i < s.size();) {
        const auto c = static_cast<unsigned char>(s[i]);
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (c < 0x20 || c == 0x7f) {
                    out += fmt::format("\\u{:04x}", c);
                } else if (c < 0x80) {
                    out.push_back(static_cast<char>(c));
                } else {
                    const size_t n = utf8_length(s, i);
                    if (n == 0) {
                        out += "\\ufffd";
                    } else {
                        out.append(s, i, n);
                        i += n;
                        continue;
                    }
                }
        }
        ++i;
    }
    out.push_back('"');
}

}  // namespace

void Json::dump(std::string& out, int indent) const {
    const std::string pad(static_cast<size_t>(indent + 2), ' ');
    switch (type_) {
        case Type::null:
            out += "null";
            break;
        case Type::boolean:
            out += bool_ ? "true" : "false";
            break;
        case Type::number:
            out += text_;
            break;
        case Type::string:
            dump_string(out, text_);
            break;
        case Type::array: {
            if (items_.empty()) {
                out += "[]";
                break;
            }
            // arrays of scalars stay on one line
            bool flat = true;
            for (const Json& j : items_)
                flat = flat && j.type_ != Type::array && j.type_ != Type::object;
            out += "[";
            for (size_t i = 0; i < items_.size(); ++i) {
                if (i > 0) out += flat ? ", " : ",";
                if (!flat) out += "\n" + pad;
                items_[i].dump(out, indent + 2);
            }
            if (!flat) out += "\n" + std::string(static_cast<size_t>(indent), ' ');
            out += "]";
            break;
        }
        case Type::object: {
            if (members_.empty()) {
                out += "{}";
                break;
            }
            out += "{";
            for (size_t i = 0; i < members_.size(); ++i) {
                if (i > 0) out += ",";
                out += "\n" + pad;
                dump_string(out, members_[i].first);
                out += ": ";
                members_[i].second.dump(out, indent + 2);
            }
            out += "\n" + std::string(static_cast<size_t>(indent), ' ') + "}";
            break;
        }
    }
}

std::string Json::dump() const {
    std::string out;
    dump(out, 0);
    out += "\n";
    return out;
}

namespace {

class Parser {
  public:
    Parser(std::string_view text, const std::string& file) : s_(text), file_(file) {}

    Json document() {
        Json v = value(0);
        skip_space();
        if (i_ < s_.size()) fail("end of file expected after the JSON value");
        return v;
    }

  private:
    [[noreturn]] void fail(const std::string& what) const {
        int line = 1;
        for (size_t k = 0; k < i_ && k < s_.size(); ++k)
            line += s_[k] == '\n';
        throw FormatError(fmt::format("{}:{}: {}", file_, line, what));
    }

    // line ends occur only here: strings hold no raw control characters
    void skip_space() {
        while (i_ < s_.size() &&
               (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) {
            line_ += s_[i_] == '\n';
            ++i_;
        }
    }

    bool take(char c) {
        skip_space();
        if (i_ < s_.size() && s_[i_] == c) {
            ++i_;
            return true;
        }
        return false;
    }

    bool word(std::string_view w) {
        if (s_.substr(i_, w.size()) == w) {
            i_ += w.size();
            return true;
        }
        return false;
    }

    Json value(int depth) {
        skip_space();
        const int line = line_;
        Json v = bare_value(depth);
        v.set_line(line);
        return v;
    }

    Json bare_value(int depth) {
        if (depth > 64) fail("JSON nested too deeply");
        if (i_ >= s_.size()) fail("JSON value expected, got the end of the file");
        const char c = s_[i_];
        if (c == '{') return object(depth);
        if (c == '[') return array(depth);
        if (c == '"') return Json(string());
        if (word("true")) return Json(true);
        if (word("false")) return Json(false);
        if (word("null")) return Json();
        if (c == '-' || (c >= '0' && c <= '9')) return number();
        const auto byte = static_cast<unsigned char>(c);
        fail(byte > 0x20 && byte < 0x7f
                 ? fmt::format("JSON value expected, got '{}'", c)
                 : fmt::format("JSON value expected, got byte 0x{:02x}", byte));
    }

    Json object(int depth) {
        ++i_;
        Json o = Json::object();
        if (take('}')) return o;
        do {
            skip_space();
            if (i_ >= s_.size() || s_[i_] != '"') fail("member name (a string) expected");
            std::string key = string();
            if (!take(':')) fail("':' expected after a member name");
            o.add(std::move(key), value(depth + 1));
        } while (take(','));
        if (!take('}')) fail("',' or '}' expected in an object");
        return o;
    }

    Json array(int depth) {
        ++i_;
        Json a = Json::array();
        if (take(']')) return a;
        do {
            a.push(value(depth + 1));
        } while (take(','));
        if (!take(']')) fail("',' or ']' expected in an array");
        return a;
    }

    static void utf8(std::string& out, unsigned cp) {
        if (cp < 0x80) {
            out.push_back(static_cast<char>(cp));
        } else if (cp < 0x800) {
            out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
            out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
        } else if (cp < 0x10000) {
            out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
            out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
            out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
        } else {
            out.push_back(static_cast<char>(0xF0 | (cp >> 18)));
            out.push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
            out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
            out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
        }
    }

    unsigned hex4() {
        if (i_ + 4 > s_.size()) fail("four hex digits expected after \\u");
        unsigned v = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = s_[i_++];
            v <<= 4;
            if (c >= '0' && c <= '9') {
                v |= static_cast<unsigned>(c - '0');
            } else if (c >= 'a' && c <= 'f') {
                v |= static_cast<unsigned>(c - 'a' + 10);
            } else if (c >= 'A' && c <= 'F') {
                v |= static_cast<unsigned>(c - 'A' + 10);
            } else {
                fail("four hex digits expected after \\u");
            }
        }
        return v;
    }

    std::string string() {
        ++i_;  // the opening quote
        std::string out;
        for (;;) {
            if (i_ >= s_.size()) fail("unterminated string");
            const char c = s_[i_++];
            if (c == '"') return out;
            if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
            if (c != '\\') {
                out.push_back(c);
                continue;
            }
            if (i_ >= s_.size()) fail("unterminated string");
            const char e = s_[i_++];
            switch (e) {
                case '"':
                case '\\':
                case '/':
                    out.push_back(e);
                    break;
                case 'b':
                    out.push_back('\b');
                    break;
                case 'f':
                    out.push_back('\f');
                    break;
                case 'n':
                    out.push_back('\n');
                    break;
                case 'r':
                    out.push_back('\r');
                    break;
                case 't':
                    out.push_back('\t');
                    break;
                case 'u': {
                    unsigned cp = hex4();
                    if (cp >= 0xD800 && cp < 0xDC00 && s_.substr(i_, 2) == "\\u") {
                        const size_t at = i_;
                        i_ += 2;
                        const unsigned lo = hex4();
                        if (lo >= 0xDC00 && lo < 0xE000) {
                            cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
                        } else {
                            i_ = at;  // not a pair: the second escape stands alone
                        }
                    }
                    // a lone surrogate is no character: U+FFFD, as in every string gaitlab writes
                    if (cp >= 0xD800 && cp < 0xE000) cp = 0xFFFD;
                    utf8(out, cp);
                    break;
                }
                default: {
                    const auto byte = static_cast<unsigned char>(e);
                    fail(byte > 0x20 && byte < 0x7f
                             ? fmt::format("unknown escape '\\{}' in a string", e)
                             : fmt::format("unknown escape: '\\' and byte 0x{:02x} in a string",
                                           byte));
                }
            }
        }
    }

    Json number() {
        const size_t start = i_;
        if (s_[i_] == '-') ++i_;
        while (i_ < s_.size() && ((s_[i_] >= '0' && s_[i_] <= '9') || s_[i_] == '.' ||
                                  s_[i_] == 'e' || s_[i_] == 'E' || s_[i_] == '+' || s_[i_] == '-'))
            ++i_;
        const std::string_view t = s_.substr(start, i_ - start);
        double v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
            fail(fmt::format("malformed number '{}'", t));
        }
        return Json::raw_number(v, std::string(t));
    }

    std::string_view s_;
    const std::string& file_;
    size_t i_ = 0;
    int line_ = 1;
};

}  // namespace

Json Json::parse(std::string_view text, const std::string& file) {
    return Parser(text, file).document();
}

}  // namespace gaitlab::data
