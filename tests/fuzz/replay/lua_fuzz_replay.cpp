// lua_fuzz_replay [--print | --verbose] INPUT...: the Lua fuzzer's harness without libFuzzer.
// Runs each input (a file, or every file of a folder) as lua_fuzz would and prints how it ended; a
// finding ends the process as it ends the fuzzer (a crash, an abort with "lua_fuzz: FINDING"),
// so ctest sees it in builds without clang or sanitizers. --print writes the script each
// input stands for instead of running it (to read a generated input that crashed); --verbose
// shows what the scripts print and the host reports.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "runner.h"
#include "script_gen.h"

namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

const char* outcome_name(gaitlab::fuzz::Outcome o) {
    switch (o) {
        case gaitlab::fuzz::Outcome::finished:
            return "finished";
        case gaitlab::fuzz::Outcome::failed:
            return "failed";
        default:
            return "interrupted";
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool print = false;
    bool verbose = false;
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--print") {
            print = true;
        } else if (arg == "--verbose") {
            verbose = true;
        } else if (fs::is_directory(arg)) {
            std::vector<fs::path> files;
            for (const auto& e : fs::directory_iterator(arg)) {
                if (e.is_regular_file() && e.path().extension() != ".md") files.push_back(e.path());
            }
            std::sort(files.begin(), files.end());
            inputs.insert(inputs.end(), files.begin(), files.end());
        } else if (fs::is_regular_file(arg)) {
            inputs.emplace_back(arg);
        } else {
            std::fprintf(stderr, "lua_fuzz_replay: no input at %s\n", arg.c_str());
            return 2;
        }
    }
    if (inputs.empty()) {
        std::fprintf(stderr, "usage: lua_fuzz_replay [--print | --verbose] FILE|FOLDER...\n");
        return 2;
    }
    if (print) {
        for (const fs::path& p : inputs) {
            const std::string bytes = read_bytes(p);
            const auto script = gaitlab::fuzz::script_for_input(
                reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
            std::printf("-- %s\n%s\n", p.string().c_str(), script.code.c_str());
        }
        return 0;
    }
    gaitlab::fuzz::Runner runner(GAITLAB_FUZZ_FIXTURES);
    runner.set_verbose(verbose);
    for (const fs::path& p : inputs) {
        std::printf("%s: running\n", p.string().c_str());
        std::fflush(stdout);
        const std::string bytes = read_bytes(p);
        const auto result = runner.run(gaitlab::fuzz::script_for_input(
            reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), true));
        const std::string first_line = result.message.substr(0, result.message.find('\n'));
        std::printf("%s: %s%s%s\n", p.string().c_str(), outcome_name(result.outcome),
                    first_line.empty() ? "" : ": ", first_line.c_str());
        std::fflush(stdout);
    }
    return 0;
}
