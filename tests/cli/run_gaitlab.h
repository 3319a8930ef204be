// Runs the gaitlab executable as a user would: arguments, a working folder, text on standard
// input (a pipe, as when answers are piped into `gaitlab new`); returns the exit status and
// what it wrote on stdout and stderr.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "temp_dir.h"

extern char** environ;

namespace gaitlab::test {

struct Output {
    int status = -1;  ///< exit status, or -1 if the process did not exit normally
    std::string out;
    std::string err;
};

/// `gaitlab ARGS...` in `cwd` with `input` on stdin; no EDITOR in its environment.
inline Output run_gaitlab(const std::vector<std::string>& args, const std::string& cwd,
                          const std::string& input = "") {
    TempDir io("run_gaitlab");
    const std::string in_path = io / "in", out_path = io / "out", err_path = io / "err";
    write_text(in_path, input);
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
    Output r;
    if (!getcwd(here, sizeof here) || chdir(cwd.c_str()) != 0) return r;
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data());
    if (chdir(here) != 0) return r;
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) return r;
    int wstatus = 0;
    if (waitpid(pid, &wstatus, 0) != pid) return r;
    r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
    r.out = read_text(out_path);
    r.err = read_text(err_path);
    return r;
}

}  // namespace gaitlab::test
