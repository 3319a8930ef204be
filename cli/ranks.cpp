// gaitlab optimize and gaitlab sweep under mpirun (see ranks.h).
#include "ranks.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/terminal.h"
#include "progress.h"

namespace gaitlab::cli {

void add_rank_timeout_option(CLI::App& command, std::string& text) {
    command
        .add_option("--rank-timeout", text,
                    "Under mpirun: seconds without a word from a rank before its evaluations "
                    "go to the others")
        ->type_name("S")
        ->capture_default_str();
}

double rank_timeout_option(const std::string& text) {
    char* end = nullptr;
    const double seconds = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(seconds > 0) || !std::isfinite(seconds)) {
        throw SpecError(
            fmt::format("--rank-timeout: a number of seconds > 0 expected (got '{}')", text));
    }
    return seconds;
}

Ranks start_ranks(const std::string& spec, optimize::MpiOptions options,
                  const std::atomic<int>* stop) {
    Ranks r;
    if (!optimize::mpi_launched()) return r;
    r.session = std::make_unique<optimize::MpiSession>();
    if (r.session->rank() > 0) {
        r.served = optimize::mpi_serve(*r.session, spec, options, stop);
        return r;
    }
    if (r.session->size() > 1) {
        options.warn = [](const std::string& m) { report_line(m); };
        r.backend = optimize::make_mpi_backend(*r.session, options);
    }
    return r;
}

int start_ranks_and_load(const std::string& file, const optimize::MpiOptions& options, Ranks& mpi,
                         optimize::Spec& spec) {
    try {
        mpi = start_ranks(file, options, &evaluations_stop());
        if (mpi.served >= 0) return mpi.served;
        spec = optimize::load_spec(file);
    } catch (const Error& e) {
        report_line(e.what());
        return 1;
    }
    return -1;
}

std::string workers_text(const Ranks& mpi, int workers) {
    return mpi.backend ? mpi.backend->describe()
                       : fmt::format("{} worker{}", workers, workers == 1 ? "" : "s");
}

}  // namespace gaitlab::cli
