// `gaitlab optimize --resume` (optimize/runner/src/run_state.cpp): a run killed (SIGKILL) or
// interrupted (SIGINT) in the middle of a generation, resumed from its results folder, ends
// with the same evaluations and best as the run that was never interrupted; a folder of another
// spec or other options, or one whose files were damaged, is refused and left as it was.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "run_gaitlab.h"

using namespace gaitlab::test;

namespace {

// a generation of 4 takes a few tenths of a second
std::string spec_of(int generations) {
    return snake_spec(fmt::format(
        R"(duration = 3, method = "cmaes", population = 4, generations = {})", generations));
}

// the line of `text` that begins with `start`
std::string line_starting(const std::string& text, const std::string& start) {
    for (const std::string& line : lines(text))
        if (line.rfind(start, 0) == 0) return line;
    return "(no line starting with '" + start + "')";
}

// best.json without the command line (it names the results folder)
std::string best_of(const std::string& path) {
    std::string out;
    for (const std::string& line : lines(read_text(path)))
        if (line.find("\"command\":") == std::string::npos) out += line + "\n";
    return out;
}

// starts gaitlab with `args`, waits until `out`/evaluations.jsonl holds `generations`
// generations' lines, lets it go on into the next one, then sends `signal`; returns the exit
// status as waitpid gives it
int interrupt_after(const std::vector<std::string>& args, const std::string& out,
                    size_t lines_written, int signal) {
    const pid_t pid = spawn_gaitlab(args, "", "/dev/null", "/dev/null", "/dev/null");
    REQUIRE(pid != 0);
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
        std::error_code ec;
        if (std::filesystem::exists(out + "/evaluations.jsonl", ec) &&
            lines(read_text(out + "/evaluations.jsonl")).size() >= lines_written)
            break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(60));
    kill(pid, signal);
    int wstatus = 0;
    REQUIRE(waitpid(pid, &wstatus, 0) == pid);
    return wstatus;
}

}  // namespace

TEST_CASE("gaitlab optimize --resume: a killed or interrupted run ends as an uninterrupted one") {
    TempDir dir("cli_optimize_resume");
    write_text(dir / "spec.lua", spec_of(6));
    const auto whole =
        run_gaitlab({"optimize", "spec.lua", "--seed", "7", "--out", "whole"}, dir.str());
    INFO(whole.err);
    REQUIRE(whole.status == 0);
    const std::vector<std::string> expected = timeless(dir / "whole/evaluations.jsonl");
    REQUIRE(expected.size() == 24);
    const std::string expected_best = best_of(dir / "whole/best.json");

    SECTION("SIGKILL in generation 3, resumed with 2 workers") {
        const int wstatus =
            interrupt_after({"optimize", dir / "spec.lua", "--seed", "7", "--out", dir / "killed"},
                            dir / "killed", 8, SIGKILL);
        REQUIRE(WIFSIGNALED(wstatus));
        const std::vector<std::string> before = timeless(dir / "killed/evaluations.jsonl");
        CHECK(before.size() >= 8);
        CHECK(before.size() < 24);
        CHECK_FALSE(std::filesystem::exists(dir / "killed/best.json"));
        const auto r = run_gaitlab({"optimize", "spec.lua", "--seed", "7", "--out", "killed",
                                    "--resume", "--workers", "2"},
                                   dir.str());
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(timeless(dir / "killed/evaluations.jsonl") == expected);
        CHECK(best_of(dir / "killed/best.json") == expected_best);
        // the same best printed, the results folder whole
        CHECK(line_starting(r.out, "best distance ") == line_starting(whole.out, "best distance "));
        CHECK(read_text(dir / "killed/convergence.csv") ==
              read_text(dir / "whole/convergence.csv"));
        CHECK(lines(r.out).back() == "convergence plot: killed/convergence.png");
        CHECK(std::filesystem::exists(dir / "killed/run/run.json"));
    }
    SECTION("SIGINT, then a line cut short as a kill in the middle of a write leaves it") {
        const int wstatus =
            interrupt_after({"optimize", dir / "spec.lua", "--seed", "7", "--out", dir / "stopped"},
                            dir / "stopped", 4, SIGINT);
        REQUIRE(WIFEXITED(wstatus));
        CHECK(WEXITSTATUS(wstatus) == 128 + SIGINT);
        const std::string jsonl = dir / "stopped/evaluations.jsonl";
        const std::string written = read_text(jsonl);
        CHECK(lines(written).size() % 4 == 0);
        write_text(jsonl, written + "{\"generation\":9,\"individ");
        const auto r = run_gaitlab(
            {"optimize", "spec.lua", "--seed", "7", "--out", "stopped", "--resume"}, dir.str());
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(timeless(jsonl) == expected);
        CHECK(best_of(dir / "stopped/best.json") == expected_best);
    }
    SECTION("a finished run resumed changes nothing") {
        const auto r = run_gaitlab(
            {"optimize", "spec.lua", "--seed", "7", "--out", "whole", "--resume"}, dir.str());
        REQUIRE(r.status == 0);
        CHECK(timeless(dir / "whole/evaluations.jsonl") == expected);
        CHECK(best_of(dir / "whole/best.json") == expected_best);
    }
}

TEST_CASE("gaitlab optimize --resume: another spec, other options or damaged files are refused") {
    TempDir dir("cli_optimize_resume_bad");
    const std::string spec = spec_of(2);
    write_text(dir / "spec.lua", spec);
    // a run stopped after its first generation: the state of generation 1, the lines of 2
    const auto r0 = run_gaitlab(
        {"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--out", "one"}, dir.str());
    REQUIRE(r0.status == 0);
    const std::string jsonl = dir / "one/evaluations.jsonl";
    const std::string written = read_text(jsonl);
    const std::string state = read_text(dir / "one/state.json");

    struct Case {
        std::vector<std::string> args;
        int status;
        std::string err;
    };
    write_text(dir / "other.lua", spec + "-- changed\n");
    std::filesystem::create_directories(dir / "empty");
    const std::vector<Case> cases = {
        {{"optimize", "spec.lua", "--resume"},
         2,
         "gaitlab: --resume: --out DIR expected (the results folder of the run to resume) (see "
         "'gaitlab optimize --help')\n"},
        {{"optimize", "spec.lua", "--resume", "--out", "none"},
         1,
         "gaitlab: --resume: --out none: no such folder (the results folder of the run to "
         "resume expected)\n"},
        {{"optimize", "spec.lua", "--resume", "--out", "empty"},
         1,
         "gaitlab: --resume: empty/state.json: missing (not the results folder of a gaitlab "
         "optimize run, or one made before runs could be resumed)\n"},
        {{"optimize", "other.lua", "--seed", "3", "--generations", "1", "--resume", "--out", "one"},
         1,
         "gaitlab: --resume: other.lua is not the spec the run in one began with (spec.lua): the "
         "spec file changed, or is another one (its text then is in one/state.json)\n"},
        {{"optimize", "spec.lua", "--seed", "4", "--generations", "1", "--resume", "--out", "one"},
         1,
         "gaitlab: --resume: --seed 4 differs from the run in one (--seed 3): resume with the "
         "options the run began with\n"},
        {{"optimize", "spec.lua", "--seed", "3", "--resume", "--out", "one"},
         1,
         "gaitlab: --resume: --generations 2 differs from the run in one (--generations 1): "
         "resume with the options the run began with\n"},
        {{"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--method", "ga", "--resume",
          "--out", "one"},
         1,
         "gaitlab: --resume: --method ga differs from the run in one (--method cmaes): resume "
         "with the options the run began with\n"},
        {{"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--population", "6",
          "--resume", "--out", "one"},
         1,
         "gaitlab: --resume: --population 6 differs from the run in one (--population 4): "
         "resume with the options the run began with\n"},
    };
    for (const Case& c : cases) {
        const auto r = run_gaitlab(c.args, dir.str());
        INFO(c.err);
        CHECK(r.status == c.status);
        CHECK(r.err == c.err);
        // nothing written or lost
        CHECK(read_text(jsonl) == written);
        CHECK(read_text(dir / "one/state.json") == state);
    }

    // evaluations.jsonl shorter than the state says: not resumed, not touched
    write_text(jsonl, written.substr(0, written.size() / 2));
    const auto r1 = run_gaitlab(
        {"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--resume", "--out", "one"},
        dir.str());
    CHECK(r1.status == 1);
    CHECK(r1.err == fmt::format("gaitlab: --resume: one/evaluations.jsonl: only {} bytes (the "
                                "run's state says {} bytes were written): not resumed\n",
                                written.size() / 2, written.size()));
    CHECK(read_text(jsonl) == written.substr(0, written.size() / 2));
    write_text(jsonl, written);

    // a damaged state
    write_text(dir / "one/state.json", state.substr(0, state.size() / 2));
    const auto r2 = run_gaitlab(
        {"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--resume", "--out", "one"},
        dir.str());
    CHECK(r2.status == 1);
    CHECK(r2.err.rfind("gaitlab: --resume: one/state.json: not a run state: ", 0) == 0);
    CHECK(read_text(jsonl) == written);
    write_text(dir / "one/state.json", "{\"format\": \"gaitlab-optimize-run\", \"version\": 7}");
    const auto r3 = run_gaitlab(
        {"optimize", "spec.lua", "--seed", "3", "--generations", "1", "--resume", "--out", "one"},
        dir.str());
    CHECK(r3.status == 1);
    CHECK(r3.err == "gaitlab: --resume: one/state.json: 'version' 7 is not known (expected 1)\n");
}
