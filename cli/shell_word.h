// A path as it must be typed in a shell command gaitlab prints for the user to paste ("Run it
// again: gaitlab run 'my snake/run.lua'"): unchanged when it holds only characters no shell
// reads specially, else in single quotes (a quote inside as '\'').
#pragma once

#include <string>
#include <string_view>

namespace gaitlab::cli {

inline std::string shell_word(std::string_view s) {
    constexpr std::string_view plain =
        "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./:@%+,=-";
    if (!s.empty() && s.find_first_not_of(plain) == std::string_view::npos) return std::string(s);
    std::string out = "'";
    for (const char c : s) {
        if (c == '\'') {
            out += "'\\''";
        } else {
            out += c;
        }
    }
    return out + "'";
}

}  // namespace gaitlab::cli
