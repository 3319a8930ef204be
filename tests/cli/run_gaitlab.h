// Runs the gaitlab executable as a user would: arguments, a working folder, text on standard
// input (a pipe, as when answers are piped into `gaitlab new`); returns the exit status and
// what it wrote on stdout and stderr. Also: starting it to interrupt it while it evaluates,
// reading a results folder, and the optimization spec the tests of gaitlab optimize, gaitlab
// sweep and gaitlab.optimize{} run.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.h"

extern char** environ;

namespace gaitlab::test {

struct Output {
    int status = -1;  ///< exit status, or -1 if the process did not exit normally
    std::string out;
    std::string err;
};

/// Starts `gaitlab ARGS...` in `cwd` ("" : this process's folder) with stdin, stdout and
/// stderr from and into the files named ("/dev/null" for none); no EDITOR in its environment.
/// Returns its pid, 0 if it could not be started.
inline pid_t spawn_gaitlab(const std::vector<std::string>& args, const std::string& cwd,
                           const std::string& in_path, const std::string& out_path,
                           const std::string& err_path) {
    std::vector<std::string> argv_s{GAITLAB_BINARY};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_s)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_s;
    for (char** e = environ; *e; ++e) {
        if (std::string(*e).rfind("EDITOR=", 0) != 0) env_s.emplace_back(*e);
    }
    std::vector<char*> env;
    for (std::string& e : env_s)
        env.push_back(e.data());
    env.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, in_path.c_str(), O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    char here[4096];
    if (!getcwd(here, sizeof here) || (!cwd.empty() && chdir(cwd.c_str()) != 0)) return 0;
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data());
    posix_spawn_file_actions_destroy(&actions);
    if (chdir(here) != 0 || rc != 0) return 0;
    return pid;
}

/// `gaitlab ARGS...` in `cwd` with `input` on stdin; no EDITOR in its environment.
inline Output run_gaitlab(const std::vector<std::string>& args, const std::string& cwd,
                          const std::string& input = "") {
    TempDir io("run_gaitlab");
    const std::string in_path = io / "in", out_path = io / "out", err_path = io / "err";
    write_text(in_path, input);
    Output r;
    const pid_t pid = spawn_gaitlab(args, cwd, in_path, out_path, err_path);
    if (pid == 0) return r;
    int wstatus = 0;
    if (waitpid(pid, &wstatus, 0) != pid) return r;
    r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
    r.out = read_text(out_path);
    r.err = read_text(err_path);
    return r;
}

/// How a process that was sent a signal ended.
struct Stopped {
    int wstatus = 0;     ///< as waitpid gives it
    double seconds = 0;  ///< wall seconds from the signal to its end
};

/// Starts `gaitlab ARGS...` in `cwd` (stdout and stderr into the files named), waits until
/// `folder`/evaluations.jsonl exists (20 s at most), then `ms` milliseconds into the
/// evaluations, sends SIGINT and waits for its end.
inline Stopped interrupt_while_evaluating(const std::vector<std::string>& args,
                                          const std::string& cwd, const std::string& folder,
                                          const std::string& out_path, const std::string& err_path,
                                          int ms = 300) {
    Stopped s;
    const pid_t pid = spawn_gaitlab(args, cwd, "/dev/null", out_path, err_path);
    if (pid == 0) return s;
    const auto start = std::chrono::steady_clock::now();
    std::error_code ec;
    while (!std::filesystem::exists(folder + "/evaluations.jsonl", ec) &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(20))
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
    const auto signalled = std::chrono::steady_clock::now();
    kill(pid, SIGINT);
    waitpid(pid, &s.wstatus, 0);
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
    return s;
}

/// An optimization spec (the text of a SPEC.lua) for the tests of gaitlab optimize, gaitlab sweep
/// and gaitlab.optimize{}: a 3-module pitch-pitch snake driven by a sine whose amplitude (10 to
/// 60 deg, initially 40) and phase (30 to 180 deg, initially 120) are the parameters, fitness
/// "distance". `settings` are the table's fields after it ("duration = 0.5, method = 'ga'");
/// `build_first`, a line build runs first, is line 4 of the file (its errors name that line);
/// `more_parameters` follow amplitude and phase ("offset = {1, 3, integer = true}"): a parameter
/// named offset is the sine's offset.
inline std::string snake_spec(const std::string& settings, const std::string& build_first = "",
                              const std::string& more_parameters = "") {
    std::string spec =
        "return {\n"
        "  parameters = { amplitude = {10, 60, initial = 40}, phase = {30, 180, initial = 120}" +
        (more_parameters.empty() ? "" : ", " + more_parameters) + " },\n  build = function(p)\n";
    if (!build_first.empty()) spec += "    " + build_first + "\n";
    return spec +
           R"(    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = p.amplitude,
                                                         phase = p.phase, frequency = 1,
                                                         offset = p.offset })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  )" + settings +
           ",\n}\n";
}

/// The lines of `text`, without their newlines.
inline std::vector<std::string> lines(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
        out.push_back(line);
    return out;
}

/// A results folder's evaluations.jsonl (`path`) without the fields that depend on timing and
/// on the workers.
inline std::vector<std::string> timeless(const std::string& path) {
    std::vector<std::string> out;
    for (const std::string& line : lines(read_text(path)))
        out.push_back(line.substr(0, line.find(",\"seconds\":")));
    return out;
}

}  // namespace gaitlab::test
