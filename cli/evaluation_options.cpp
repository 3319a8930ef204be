// The options gaitlab optimize and gaitlab sweep share (see evaluation_options.h).
#include "evaluation_options.h"

#include "ranks.h"

namespace gaitlab::cli {

void add_evaluation_options(CLI::App& command, EvaluationArgs& args, const std::string& seed_help) {
    command
        .add_option("--workers", args.workers,
                    "Threads evaluating in parallel, each with its own Lua state (the results "
                    "are the same for any number)")
        ->type_name("N")
        ->capture_default_str();
    command.add_option("--seed", args.seed, seed_help + ": 0 to 2^64 - 1")
        ->type_name("N")
        ->capture_default_str();
    add_rank_timeout_option(command, args.rank_timeout);
    command
        .add_option("--out", args.out,
                    "Results folder, new or empty (default: runs/" + command.get_name() +
                        "-SPEC-DATE-TIME)")
        ->type_name("DIR");
}

}  // namespace gaitlab::cli
