// Suggestions for misspelt names in error messages ("did you mean 'amplitude'?").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gaitlab {

/// The candidates close to `word` (edit distance at most max(2, length / 3)), closest first
/// (ties in their order), at most `n`.
std::vector<std::string> closest_names(std::string_view word,
                                       const std::vector<std::string>& candidates, size_t n = 3);
/// The candidate closest to `word`, or "" if none is close.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);
/// "; did you mean 'x'?" or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);
/// "; did you mean 'a', 'b' or 'c'?" for up to three close candidates, or "".
std::string suggest(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace gaitlab
