#include "gaitlab/terminal.h"

#include <cstdarg>

namespace gaitlab {

namespace {

// the length of the valid UTF-8 sequence of two to four bytes at text[i], its code point in
// `cp`; 0 if there is none (a lone or cut sequence, an overlong form, a surrogate, past
// U+10FFFF)
size_t utf8_sequence(std::string_view text, size_t i, char32_t& cp) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char c = byte(i);
    size_t n = 0;
    if ((c & 0xe0) == 0xc0) {
        n = 2;
        cp = c & 0x1fu;
    } else if ((c & 0xf0) == 0xe0) {
        n = 3;
        cp = c & 0x0fu;
    } else if ((c & 0xf8) == 0xf0) {
        n = 4;
        cp = c & 0x07u;
    } else {
        return 0;
    }
    if (text.size() - i < n) return 0;
    for (size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xc0) != 0x80) return 0;
        cp = (cp << 6) | (byte(i + k) & 0x3fu);
    }
    const char32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < least[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
    return n;
}

void escape(std::string& out, unsigned char c) {
    constexpr char kHex[] = "0123456789abcdef";
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 0xf];
}

// terminal_text, and with `one_line` terminal_line
std::string escaped(std::string_view text, bool one_line) {
    std::string out;
    out.reserve(text.size());
    size_t i = 0;
    while (i < text.size()) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x80) {
            if ((c < 0x20 && ((c != '\n' && c != '\t') || one_line)) || c == 0x7f) {
                escape(out, c);
            } else {
                out += static_cast<char>(c);
            }
            ++i;
            continue;
        }
        char32_t cp = 0;
        const size_t n = utf8_sequence(text, i, cp);
        if (n == 0) {
            escape(out, c);  // the next byte starts afresh
            ++i;
        } else if (cp <= 0x9f) {
            for (size_t k = 0; k < n; ++k)
                escape(out, static_cast<unsigned char>(text[i + k]));
            i += n;
        } else {
            out.append(text, i, n);
            i += n;
        }
    }
    return out;
}

}  // namespace

std::string terminal_text(std::string_view text) {
    return escaped(text, false);
}

std::string terminal_line(std::string_view text) {
    return escaped(text, true);
}

void write_message(std::FILE* stream, std::string_view text) {
    const std::string out = terminal_text(text);
    std::fwrite(out.data(), 1, out.size(), stream);
}

void report_line(std::string_view message) {
    std::string text = "gaitlab: ";
    text += message;
    text += '\n';
    write_message(stderr, text);
}

void print_message(std::FILE* stream, const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list again;
    va_copy(again, args);
    const int n = std::vsnprintf(nullptr, 0, format, args);
    va_end(args);
    std::string text;
    if (n > 0) {
        text.resize(static_cast<size_t>(n) + 1);
        std::vsnprintf(text.data(), text.size(), format, again);
        text.resize(static_cast<size_t>(n));
    }
    va_end(again);
    write_message(stream, text);
}

}  // namespace gaitlab
