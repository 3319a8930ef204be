#include "console_command.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "console_frontend.h"
#include "gaitlab/files.h"
#include "gaitlab/scripting/console.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/terminal.h"
#include "gaitlab/version.h"
#include "gaitlab/viewer/view.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

// the console's host, while the console runs (the handlers interrupt it)
std::atomic<scripting::LuaHost*> g_host{nullptr};
// a typed line (or the -i script) is running: Ctrl-C interrupts it, else it clears the prompt
volatile std::sig_atomic_t g_running = 0;
// SIGTERM or SIGHUP received: the console ends
volatile std::sig_atomic_t g_terminate = 0;
static_assert(std::atomic<scripting::LuaHost*>::is_always_lock_free);

extern "C" void on_console_signal(int sig) {
    scripting::LuaHost* host = g_host.load();
    if (sig == SIGINT) {
        if (g_running && host) {
            host->interrupt(SIGINT);
        } else {
            LineInput::interrupt_prompt();
        }
        return;
    }
    // a second one while the recordings close: end now (what was flushed stays)
    if (g_terminate != 0) _exit(128 + sig);
    g_terminate = sig;
    if (host) host->interrupt(sig);
    LineInput::interrupt_prompt();
}

// no SA_RESTART: the wait for a key returns and sees what happened
void catch_console_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_console_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaction(sig, &sa, nullptr);
}

// the error of a line or script, with its traceback
std::string error_text(const scripting::ScriptError& e) {
    std::string text = e.what();
    if (!e.traceback().empty()) text += "\n" + e.traceback();
    return text + "\n";
}

}  // namespace

CLI::App* add_console_command(CLI::App& app, ConsoleArgs& a) {
    CLI::App* c = app.add_subcommand(
        "console",
        "Open the interactive Lua console, after running FILE.lua if given (also: 'gaitlab' "
        "alone, 'gaitlab -i FILE.lua')");
    c->allow_extras();
    c->add_option("file", a.file, "A script to run first; its globals stay (FILE.lua)");
    c->add_option("args", a.args, "Arguments for the script: arg[1], arg[2], ...")
        ->type_name("ARGS");
    c->add_option("--seed", a.seed, "Seed for everything random (math.random too): 0 to 2^64 - 1")
        ->type_name("N")
        ->capture_default_str();
    auto* record = c->add_option("--record", a.record,
                                 "Record the first simulation into DIR (default: "
                                 "runs/NAME-DATE-TIME)");
    record->type_name("DIR");
    auto* no_record = c->add_flag("--no-record", a.no_record, "Record nothing");
    record->excludes(no_record);
    c->footer(
        "Lines are Lua, run as they are typed; '=expr' or a bare expression prints its value.\n"
        "Simulations record into run folders as with 'gaitlab run'; Ctrl-D closes them and\n"
        "exits. Ctrl-C stops a running command, or clears the line being typed. History:\n"
        "$XDG_STATE_HOME/gaitlab/history. When stdin is not a terminal, lines are read as they\n"
        "come, without prompts or line editing. See docs/console.md.");
    return c;
}

int run_console(const ConsoleArgs& a, const std::string& command,
                const std::function<void(scripting::LuaHost&)>& prepare) {
    std::uint64_t seed = 0;
    {
        const char* end = a.seed.data() + a.seed.size();
        const auto r = std::from_chars(a.seed.data(), end, seed);
        if (a.seed.empty() || r.ec != std::errc() || r.ptr != end) {
            print_message(stderr,
                          "gaitlab: --seed: a whole number from 0 to 18446744073709551615 "
                          "expected (got '%s') (see 'gaitlab console --help')\n",
                          a.seed.c_str());
            return 2;
        }
    }
    if (!a.file.empty() && (a.file.size() < 4 || a.file.substr(a.file.size() - 4) != ".lua")) {
        print_message(stderr, "gaitlab: %s: expected a Lua script (FILE.lua)\n", a.file.c_str());
        return 2;
    }
    const bool terminal = ::isatty(0) != 0;
    std::vector<std::string> folders;
    int status = 0;
    try {
        scripting::LuaHost host;
        scripting::RecordSettings rec;
        rec.by_default = true;
        rec.disabled = a.no_record;
        rec.dir = a.record;
        rec.name = a.file.empty() ? "console" : fs::path(a.file).stem().string();
        rec.script = a.file;
        rec.command = command;
        host.set_recording(rec);
        host.seed(seed);
        host.set_args(a.file, a.args);
        if (prepare) prepare(host);
        // the browser viewer, made by the first sim:view() (it goes before the host)
        std::unique_ptr<viewer::View> view;
        std::string served_host;  // where it listens

        scripting::Console console(host);
        LineInput::Options options;
        options.terminal = terminal;
        options.history_file = terminal ? default_history_file() : "";
        options.complete = [&console](std::string_view before) { return console.complete(before); };
        // simulations play (sim:play()) while the prompt waits for a key, and the viewer's
        // pages are served
        options.idle = [&host, &view] {
            const double wait = host.pump();
            return view ? std::min(wait, view->poll()) : wait;
        };
        options.warn = [](const std::string& message) {
            write_message(stderr, "gaitlab: warning: " + message + "\n");
        };
        LineInput input(std::move(options));
        console.set_writers([&input](const std::string& t) { input.write(stdout, t); },
                            [&input](const std::string& t) { input.write(stderr, t); });
        host.set_output([&input](const std::string& t) { input.write(stdout, t); });
        host.set_reporter([&input, &view](const std::string& m) {
            input.write(stderr, terminal_text("gaitlab: " + m + "\n"));
            if (view) view->message("error", m);
        });
        // sim:view(): the page and this console steer the simulation together
        host.set_view_handler([&](const std::shared_ptr<Player>& player, int index,
                                  const scripting::LuaHost::ViewRequest& request) {
            if (view && ((request.port != 0 && request.port != view->server().port()) ||
                         (!request.host.empty() && request.host != served_host))) {
                throw Error(
                    fmt::format("sim:view(): the viewer serves {} already (port and "
                                "host choose where the first sim:view() serves it)",
                                view->url()));
            }
            if (!view) {
                viewer::ViewOptions o;
                o.wait_for_page = false;
                o.console = true;
                viewer::ServerOptions where;
                where.port = request.port;
                if (!request.host.empty()) where.host = request.host;
                // the same rules as --view: beyond loopback, a token in every request
                view = std::make_unique<viewer::View>(host, where, o);
                served_host = where.host;
                // "Edit world" saves beside the script (or in the current folder)
                view->edit_world((a.file.empty()
                                      ? fs::path("world")
                                      : fs::path(a.file).parent_path() / fs::path(a.file).stem())
                                     .string() +
                                 ".environment.xml");
                input.write(stderr, "viewer: " + terminal_text(view->url()) +
                                        "\n  open it in a browser: the page and this console "
                                        "work together (sim:run plays at real time)\n");
                if (where.host == "0.0.0.0" || where.host == "::") {
                    input.write(stderr,
                                "  from another machine: this machine's address in place of "
                                "127.0.0.1, with the token (whoever has it can steer the "
                                "simulation)\n");
                }
            }
            view->show(player, index);
            return view->url();
        });

        struct Interruptible {
            explicit Interruptible(scripting::LuaHost& h) { g_host.store(&h); }
            ~Interruptible() { g_host.store(nullptr); }
        } interruptible(host);
        catch_console_signals();

        if (!a.file.empty()) {
            // a script that cannot be read is an error, as for `gaitlab run`; one that fails
            // shows its error, and the console opens with what it defined
            (void)gaitlab::read_file(a.file);
            g_running = 1;
            try {
                host.run_file(a.file);
            } catch (const scripting::ScriptError& e) {
                input.write(stderr, terminal_text(error_text(e)));
            }
            g_running = 0;
            host.clear_interrupt();
        } else if (terminal) {
            input.write(stdout, std::string("gaitlab ") + gaitlab::version() +
                                    " console, Lua 5.4 (Ctrl-D exits; docs/console.md)\n");
        }
        while (g_terminate == 0) {
            const LineInput::Line line = input.read(console.prompt());
            if (g_terminate != 0) break;
            if (line.kind == LineInput::Line::Kind::end) break;
            if (line.kind == LineInput::Line::Kind::interrupted) {
                // Ctrl-C at the prompt: the line goes, and what plays stops (a stop button)
                console.discard();
                if (const int n = host.pause_all(); n > 0) {
                    input.write(stderr, fmt::format("paused {} simulation{} (sim:play() goes on)\n",
                                                    n, n == 1 ? "" : "s"));
                }
                continue;
            }
            g_running = 1;
            const scripting::Console::Status s = console.feed(line.text);
            g_running = 0;
            if (s != scripting::Console::Status::more) input.add_history(console.last_chunk());
        }
        // nothing may reach `input` once it is gone
        host.set_view_handler({});
        host.set_output({});
        host.set_reporter([](const std::string& m) { report_line(m); });
        // a signal closes the recordings as interrupted, as `gaitlab run` does
        if (g_terminate != 0) host.interrupt(g_terminate);
        try {
            host.finish();
        } catch (const std::exception& e) {
            report_line(e.what());
            status = 1;
        }
        folders = host.run_folders();
    } catch (const std::exception& e) {
        report_line(e.what());
        status = 1;
    }
    for (const std::string& f : folders)
        print_message(stderr, "recorded %s\n", f.c_str());
    if (g_terminate != 0) return 128 + g_terminate;
    return status;
}

}  // namespace gaitlab::cli
