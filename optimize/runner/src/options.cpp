// The options of a run, checked the same way for the command line and Lua (options.h).
#include "gaitlab/optimize/options.h"

#include <charconv>
#include <utility>

#include <fmt/format.h>

namespace gaitlab::optimize {

namespace {

std::string spelled(const std::string& option, OptionGiver giver) {
    return giver == OptionGiver::command_line ? "--" + option : option;
}

}  // namespace

OptionError::OptionError(std::string option, std::string problem, OptionGiver giver)
    : SpecError(spelled(option, giver) + ": " + problem),
      option_(std::move(option)),
      problem_(std::move(problem)) {}

std::uint64_t whole_number(const std::string& option, const std::string& text, std::uint64_t min,
                           std::uint64_t max, OptionGiver giver) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || v < min || v > max) {
        throw OptionError(
            option, fmt::format("a whole number from {} to {} expected (got '{}')", min, max, text),
            giver);
    }
    return v;
}

RunOptions check_options(const GivenOptions& given, OptionGiver giver) {
    RunOptions o;
    if (!given.generations.empty()) {
        o.generations =
            static_cast<int>(whole_number("generations", given.generations, 1, 1000000000, giver));
    }
    if (!given.population.empty()) {
        o.population =
            static_cast<int>(whole_number("population", given.population, 1, 1000000000, giver));
    }
    if (!given.workers.empty()) {
        o.workers = static_cast<int>(whole_number("workers", given.workers, 1, 1024, giver));
    }
    if (!given.seed.empty()) o.seed = whole_number("seed", given.seed, 0, UINT64_MAX, giver);
    o.method = given.method;
    o.out = given.out;
    o.resume = given.resume;
    if (o.resume && o.out.empty()) {
        throw OptionError(
            "resume",
            fmt::format("{} expected (the results folder of the run to resume)",
                        giver == OptionGiver::command_line ? "--out DIR" : "out = DIR"),
            giver);
    }
    if (!o.method.empty() && o.method != "ga" && o.method != "cmaes" && o.method != "pgpe") {
        throw OptionError("method",
                          fmt::format("unknown method '{}' (expected ga, cmaes or pgpe)", o.method),
                          giver);
    }
    return o;
}

}  // namespace gaitlab::optimize
