// Suggestions for misspelt names in error messages ("did you mean 'amplitude'?").
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace gaitlab {

/// The candidate closest to `word` by edit distance, or "" if none is close.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);
/// "; did you mean 'x'?" or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace gaitlab
