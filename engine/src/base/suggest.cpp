#include "gaitlab/suggest.h"

#include <algorithm>

namespace gaitlab {

namespace {

size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
            diag = up;
        }
    }
    return row[b.size()];
}

}  // namespace

std::vector<std::string> closest_names(std::string_view word,
                                       const std::vector<std::string>& candidates, size_t n) {
    const size_t limit = std::max<size_t>(2, word.size() / 3);
    std::vector<std::pair<size_t, size_t>> scored;  // distance, index
    for (size_t i = 0; i < candidates.size(); ++i) {
        const size_t d = edit_distance(word, candidates[i]);
        if (d <= limit) scored.emplace_back(d, i);
    }
    std::stable_sort(scored.begin(), scored.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (size_t i = 0; i < scored.size() && out.size() < n; ++i)
        out.push_back(candidates[scored[i].second]);
    return out;
}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
    const std::vector<std::string> c = closest_names(word, candidates, 1);
    return c.empty() ? "" : c[0];
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string c = closest(word, candidates);
    return c.empty() ? "" : "; did you mean '" + c + "'?";
}

std::string suggest(std::string_view word, const std::vector<std::string>& candidates) {
    const std::vector<std::string> c = closest_names(word, candidates);
    if (c.empty()) return "";
    std::string s = "; did you mean ";
    for (size_t i = 0; i < c.size(); ++i) {
        if (i > 0) s += i + 1 == c.size() ? " or " : ", ";
        s += "'" + c[i] + "'";
    }
    return s + "?";
}

}  // namespace gaitlab
