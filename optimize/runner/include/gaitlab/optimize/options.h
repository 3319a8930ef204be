// The options of a run as its two givers give them — `gaitlab optimize SPEC.lua --generations N
// ...` on the command line and `gaitlab.optimize{ spec =, generations =, ... }` in Lua — and the
// one set of checks both go through (docs/optimization.md). Only the spelling of an option in
// messages differs: "--generations" or "generations".
#pragma once

#include <cstdint>
#include <string>

#include "gaitlab/error.h"
#include "gaitlab/optimize/runner.h"

namespace gaitlab::optimize {

/// Who gives the options, for the way messages spell them.
enum class OptionGiver {
    command_line,  ///< "--generations", "--out DIR"
    lua,           ///< "generations", "out = DIR"
};

/// The options as given, each as its text ("" : not given, the default): the command line's
/// words, or a Lua table's values written as decimal text.
struct GivenOptions {
    std::string method;       ///< "ga", "cmaes" or "pgpe"; "" : the spec's
    std::string generations;  ///< 1 to 10^9; "" : the spec's
    std::string population;   ///< 1 to 10^9; "" : the spec's, or the method's
    std::string workers;      ///< 1 to 1024; "" : 1
    std::string seed;         ///< 0 to 2^64 - 1; "" : 0
    std::string out;          ///< the results folder; "" : none given (resume needs one)
    bool resume = false;
};

/// A bad option: `option()` its name ("generations"), `problem()` what is wrong ("a whole
/// number from 1 to 1000000000 expected (got '0')"); what() is both, the name as the giver
/// spells it ("--generations: a whole number ...").
class OptionError : public SpecError {
  public:
    OptionError(std::string option, std::string problem, OptionGiver giver);
    const std::string& option() const { return option_; }
    const std::string& problem() const { return problem_; }

  private:
    std::string option_;
    std::string problem_;
};

/// A whole number in [min, max] from `text` (decimal digits only); OptionError "OPTION: a whole
/// number from MIN to MAX expected (got 'TEXT')" otherwise.
std::uint64_t whole_number(const std::string& option, const std::string& text, std::uint64_t min,
                           std::uint64_t max, OptionGiver giver = OptionGiver::command_line);

/// Checks `given` into the options of run_optimization: method, generations, population,
/// workers, seed, out (as given: "" stays "") and resume. Throws OptionError for the first bad
/// one. `command` and `backend` are left for the caller.
RunOptions check_options(const GivenOptions& given, OptionGiver giver);

}  // namespace gaitlab::optimize
