// The gaitlab executable: gaitlab run FILE.lua|FILE.xml (recorded to runs/ by default),
// gaitlab FILE.lua, gaitlab data DIR (list, extract, export, plot recorded series), gaitlab
// replay DIR, gaitlab optimize SPEC.lua (optimize.h), gaitlab sweep SPEC.lua (sweep.h), --help,
// --version; gaitlab alone and gaitlab -i FILE.lua open the console (console_command.h).
//
// The command line is strict: an option gaitlab does not know is an error (with the closest
// one), wherever it stands; the script's own arguments follow FILE, after "--" as soon as one
// starts with '-'. Everything gaitlab writes to standard output goes through one checked
// writer, and a write that failed makes the exit status non-zero. SIGINT, SIGTERM, SIGHUP and
// SIGPIPE stop `gaitlab run` and `gaitlab replay` cleanly: their run folders are closed as
// "interrupted" and the exit status is 128 + the signal.
#include <fcntl.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "console_command.h"
#include "edit.h"
#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/run_data.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/scripting/replay.h"
#include "gaitlab/suggest.h"
#include "gaitlab/terminal.h"
#include "gaitlab/version.h"
#include "gaitlab/viewer/run_view.h"
#include "gaitlab/viewer/view.h"
#include "gaitlab/xml.h"
#include "make.h"
#include "optimize.h"
#include "progress.h"
#include "sweep.h"
#include "wizard.h"

namespace {

namespace fs = std::filesystem;
using gaitlab::print_message;
using gaitlab::report_line;
using gaitlab::terminal_line;

bool ends_with(const std::string& s, const char* suffix) {
    const std::string x(suffix);
    return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

// ---------------------------------------------------------------------------------------------
// standard output

// Every byte gaitlab writes to stdout goes through here, and finish() checks what the script
// wrote there too (print, io.write share the same FILE): a full disk, a closed stdout or a
// broken pipe is never reported as success.
class Stdout {
  public:
    // writes `text`; false once a write failed (later writes are skipped)
    static bool write(std::string_view text) {
        if (failed()) return false;
        if (!text.empty() && std::fwrite(text.data(), 1, text.size(), stdout) != text.size()) {
            error_ = errno != 0 ? errno : EIO;
        }
        return !failed();
    }
    template <typename... T>
    static bool print(fmt::format_string<T...> format, T&&... args) {
        return write(fmt::format(format, std::forward<T>(args)...));
    }
    static bool failed() { return error_ != 0 || std::ferror(stdout); }

    // flushes stdout; returns `status` if everything reached it, else the status of the failure
    // (1 with one line on stderr; 128 + SIGPIPE, quietly, for a reader that went away, as if
    // the signal had ended the process; a non-zero `status` stays)
    static int finish(int status) {
        errno = 0;
        if (std::fflush(stdout) != 0 && error_ == 0) error_ = errno != 0 ? errno : EIO;
        if (!failed()) return status;
        // a command that failed already said why
        if (status != 0) return status;
        if (error_ == EPIPE) return 128 + SIGPIPE;
        if (error_ != 0) {
            print_message(stderr, "gaitlab: cannot write to standard output: %s\n",
                          std::strerror(error_));
        } else {
            // the script's own writes failed (print, io.write): their reason is gone
            print_message(stderr,
                          "gaitlab: cannot write to standard output: some of the output was "
                          "lost\n");
        }
        return 1;
    }

  private:
    static inline int error_ = 0;
};

// a closed stdin, stdout or stderr (`gaitlab ... >&-`) would be the next file gaitlab opens (a
// run folder's data.csv would get what print writes): put /dev/null there, opened so that
// writes fail (EBADF) and are reported instead of vanishing
void keep_standard_streams() {
    for (int fd = 0; fd <= 2; ++fd) {
        if (::fcntl(fd, F_GETFD) >= 0 || errno != EBADF) continue;
        const int null = ::open("/dev/null", O_RDONLY);
        if (null >= 0 && null != fd) {
            ::dup2(null, fd);
            ::close(null);
        }
    }
}

// one CSV field, quoted if it needs to be (RFC 4180), as the run folders write them
std::string csv_field(std::string_view s) {
    if (s.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(s);
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

// ---------------------------------------------------------------------------------------------
// signals

// the host `gaitlab run` runs, while it runs (the handler interrupts it)
std::atomic<gaitlab::scripting::LuaHost*> g_host{nullptr};
// the first signal received, 0 if none
volatile std::sig_atomic_t g_signal = 0;
static_assert(std::atomic<gaitlab::scripting::LuaHost*>::is_always_lock_free);

extern "C" void on_signal(int sig) {
    if (g_signal != 0) {
        // a second signal while the run folders close: end now (what was flushed stays); a
        // broken pipe again is no reason to give up closing
        if (sig != SIGPIPE) _exit(128 + sig);
        return;
    }
    g_signal = sig;
    if (gaitlab::scripting::LuaHost* host = g_host.load()) host->interrupt(sig);
    gaitlab::cli::stop_evaluations(sig);
}

const char* strsignal_name(int sig) {
    switch (sig) {
        case SIGINT:
            return "SIGINT";
        case SIGTERM:
            return "SIGTERM";
        case SIGHUP:
            return "SIGHUP";
        default:
            return "SIGPIPE";
    }
}

// SIGINT, SIGTERM, SIGHUP and SIGPIPE interrupt the host; no SA_RESTART, so a script waiting
// on input (io.read) sees the call fail and stops at its next instruction
void catch_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE})
        sigaction(sig, &sa, nullptr);
}

// from its making a signal interrupts the host (one that came earlier does so at once), until
// it goes
struct Interruptible {
    explicit Interruptible(gaitlab::scripting::LuaHost& h) {
        g_host.store(&h);
        if (g_signal != 0) h.interrupt(g_signal);
    }
    ~Interruptible() { g_host.store(nullptr); }
    Interruptible(const Interruptible&) = delete;
    Interruptible& operator=(const Interruptible&) = delete;
};

// ---------------------------------------------------------------------------------------------
// option values

// a whole number in [0, 2^64 - 1]; SpecError naming the option otherwise
std::uint64_t parse_seed(const std::string& text) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end) {
        throw gaitlab::SpecError(fmt::format(
            "--seed: a whole number from 0 to 18446744073709551615 expected (got '{}')", text));
    }
    return v;
}

// a finite number of seconds; SpecError naming the option otherwise
double parse_seconds(const char* option, std::string text) {
    if (!text.empty() && text[0] == '+') text.erase(0, 1);
    double v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) {
        throw gaitlab::SpecError(
            fmt::format("{}: a number of seconds expected (got '{}')", option, text));
    }
    return v;
}

// ---------------------------------------------------------------------------------------------
// gaitlab run

struct RunArgs {
    std::string file;
    std::vector<std::string> args;  // the script's
    std::string seed = "0";
    std::string record;
    bool no_record = false;
    bool no_progress = false;
    bool view = false;  // --view: serve the viewer
    std::string port;   // --port
    std::string host;   // --host
};

// --port: a whole number in [1, 65535]; SpecError naming the option otherwise
int parse_port(const std::string& text) {
    int v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || v < 1 || v > 65535) {
        throw gaitlab::SpecError(
            fmt::format("--port: a port number from 1 to 65535 expected (got '{}'; leave --port "
                        "out for any free port)",
                        text));
    }
    return v;
}

struct CheckArgs {
    std::string file;
    std::string seconds, cycle, settle;  // as given ("": the check's default)
};

// `gaitlab check FILE.xml`: the accuracy check of a simulation file (LuaHost::
// check_simulation_file); exit status 0 within 3 %, 3 a setting warned, 1 or 2 an error
int check_command(const CheckArgs& a) {
    if (!ends_with(a.file, ".xml")) {
        print_message(stderr,
                      "gaitlab: %s: expected a simulation file (FILE.xml); a Lua script checks "
                      "its simulation itself with sim:check_accuracy{} (docs/lua-api.md)\n",
                      a.file.c_str());
        return 2;
    }
    struct stat st {};
    if (::stat(a.file.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        print_message(stderr, "gaitlab: %s: %s\n", a.file.c_str(),
                      S_ISDIR(st.st_mode) ? "is a directory"
                                          : "not a regular file (a FIFO, device or socket)");
        return 2;
    }
    double seconds = 0, cycle = 0, settle = 0;
    try {
        // at most a million simulated seconds: more would be blamed on the file's line by the
        // simulation that cannot run it
        const auto positive = [](const char* option, const std::string& text) {
            if (text.empty()) return 0.0;
            const double v = parse_seconds(option, text);
            if (!(v > 0)) {
                throw gaitlab::SpecError(
                    fmt::format("{}: a number of seconds > 0 expected (got '{}')", option, text));
            }
            if (!(v <= 1e6)) {
                throw gaitlab::SpecError(fmt::format(
                    "{}: a number of seconds up to 1e6 expected (got '{}')", option, text));
            }
            return v;
        };
        seconds = positive("--seconds", a.seconds);
        cycle = positive("--cycle", a.cycle);
        if (!a.settle.empty()) {
            settle = parse_seconds("--settle", a.settle);
            if (!(settle >= 0 && settle <= 1e6)) {
                throw gaitlab::SpecError(fmt::format(
                    "--settle: a number of seconds from 0 to 1e6 expected (got '{}')", a.settle));
            }
        }
    } catch (const gaitlab::Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab check --help')\n", e.what());
        return 2;
    }
    std::string error;
    int warned = 0;
    try {
        gaitlab::scripting::LuaHost host;
        host.set_reporter([](const std::string& message) { report_line(message); });
        const Interruptible interruptible(host);
        warned = host.check_simulation_file(a.file, seconds, cycle, settle);
    } catch (const std::exception& e) {
        error = e.what();
    }
    if (g_signal != 0) {
        if (g_signal != SIGPIPE) {
            report_line(error.empty() ? "interrupted" : error);
        }
        return 128 + g_signal;
    }
    if (!error.empty()) {
        report_line(error);
        return 1;
    }
    return warned > 0 ? 3 : 0;
}

// The progress line of a long sim:run(T) (or the duration of a simulation file) on a terminal:
// "t = 12.0 / 60 s (20%), 4.1x real time, 12 s left", rewritten in place on stderr, taken away
// before anything else is written there and when the run ends. Never on stdout (which holds
// the script's data), and only when stderr is a terminal.
class ProgressLine {
  public:
    void show(const gaitlab::scripting::RunProgress& p) {
        if (p.done) {
            clear();
            return;
        }
        const double done = p.time - p.start;
        const double factor = p.wall > 0 ? done / p.wall : 0;
        std::string line = fmt::format("t = {:.1f} / {:g} s", p.time, p.end);
        if (p.end > p.start) {
            line += fmt::format(" ({:.0f}%)", 100 * done / (p.end - p.start));
        }
        if (factor > 0) {
            line += fmt::format(", {:.2g}x real time, {} left", factor,
                                duration((p.end - p.time) / factor));
        }
        // a line longer than the terminal would wrap, and \r would not take it all away
        winsize ws{};
        if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 1 &&
            line.size() >= ws.ws_col) {
            line.resize(ws.ws_col - 1U);
        }
        std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
        std::fflush(stderr);
        shown_ = true;
    }
    // takes the line away (before a message, and at the end)
    void clear() {
        if (!shown_) return;
        std::fputs("\r\x1b[K", stderr);
        std::fflush(stderr);
        shown_ = false;
    }

  private:
    static std::string duration(double s) {
        if (!(s >= 1)) return "<1 s";
        if (s >= 1e9) return "ages";  // a crawling run of a long duration
        const long n = std::lround(s);
        if (n < 60) return fmt::format("{} s", n);
        if (n < 3600) return fmt::format("{} min {:02} s", n / 60, n % 60);
        return fmt::format("{} h {:02} min", n / 3600, n % 3600 / 60);
    }
    bool shown_ = false;
};

int run_script(const RunArgs& a, const std::string& command) {
    const bool xml = ends_with(a.file, ".xml");
    if (!ends_with(a.file, ".lua") && !xml) {
        print_message(stderr,
                      "gaitlab: %s: expected a Lua script (FILE.lua) or a simulation file "
                      "(FILE.xml)\n",
                      a.file.c_str());
        return 2;
    }
    // a FIFO or a device would block or never end: only a regular file is a script (a missing
    // one is reported by the host, naming it as Lua does)
    struct stat st {};
    if (::stat(a.file.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        print_message(stderr, "gaitlab: %s: %s\n", a.file.c_str(),
                      S_ISDIR(st.st_mode) ? "is a directory"
                                          : "not a regular file (a FIFO, device or socket)");
        return 2;
    }
    std::uint64_t seed = 0;
    gaitlab::viewer::ServerOptions server;
    try {
        seed = parse_seed(a.seed);
        if (!a.port.empty()) server.port = parse_port(a.port);
        if (!a.host.empty()) server.host = a.host;
    } catch (const gaitlab::Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab run --help')\n", e.what());
        return 2;
    }
    std::vector<std::string> folders;
    std::string error;
    // Ctrl-C ended the viewer after the script: the way to quit, not an interruption
    bool quit_viewer = false;
    try {
        gaitlab::scripting::LuaHost host;
        ProgressLine progress;
        // the viewer goes before the host: its simulations' controllers live in the host
        std::unique_ptr<gaitlab::viewer::View> view;
        if (a.view) {
            try {
                view = std::make_unique<gaitlab::viewer::View>(host, server);
            } catch (const gaitlab::Error& e) {
                report_line(e.what());
                return 1;
            }
            print_message(stderr,
                          "viewer: %s\n  open it in a browser: the simulation starts when the page "
                          "opens (Ctrl-C quits)\n",
                          view->url().c_str());
            if (server.host == "0.0.0.0" || server.host == "::") {
                print_message(stderr,
                              "  from another machine: this machine's address in place of "
                              "127.0.0.1, with the token (whoever has it can steer the "
                              "simulation)\n");
            }
            // "Edit world" saves the simulation file's environment, or one beside the script
            std::string world = (fs::path(a.file).parent_path() /
                                 (fs::path(a.file).stem().string() + ".environment.xml"))
                                    .string();
            if (xml) {
                try {
                    world =
                        gaitlab::resolve_path(a.file, gaitlab::read_simulation(a.file).environment);
                } catch (const gaitlab::Error&) {
                    // running the file says what is wrong with it
                }
            }
            view->edit_world(world);
        }
        if (view) {
            // sim:view() shows that simulation (every one is shown already, the newest first)
            host.set_view_handler([&view](const std::shared_ptr<gaitlab::Player>& p, int index,
                                          const gaitlab::scripting::LuaHost::ViewRequest& r) {
                // the viewer listens where --port and --host said, before the script ran
                if ((r.port != 0 && r.port != view->server().port()) || !r.host.empty()) {
                    throw gaitlab::Error(fmt::format(
                        "sim:view(): the viewer serves {} already: under gaitlab run --view, "
                        "choose its port and address with --port and --host",
                        view->url()));
                }
                view->show(p, index);
                return view->url();
            });
        }
        // failed reloads of controller files and controllers failing under
        // on_controller_error = "continue" are reported while the script goes on
        host.set_reporter([&progress, &view](const std::string& message) {
            progress.clear();
            report_line(message);
            if (view) view->message("error", message);
        });
        if (!a.no_progress && ::isatty(STDERR_FILENO)) {
            host.set_progress(
                [&progress](const gaitlab::scripting::RunProgress& p) { progress.show(p); });
        }
        gaitlab::scripting::RecordSettings rec;
        rec.by_default = true;
        rec.disabled = a.no_record;
        rec.dir = a.record;
        rec.name = fs::path(a.file).stem().string();
        rec.script = a.file;
        rec.command = command;
        host.set_recording(rec);
        host.seed(seed);
        host.set_args(a.file, a.args);
        // gaitlab.optimize{...}: stopped by the signal that interrupts the host
        host.set_optimize_handler(gaitlab::cli::lua_optimize_handler());
        const Interruptible interruptible(host);
        try {
            if (xml) {
                host.run_simulation_file(a.file);
            } else {
                host.run_file(a.file);
            }
        } catch (const std::exception& e) {
            error = e.what();
        }
        progress.clear();
        if (view && g_signal == 0) {
            // the student looks on (and plays on) after the script, until Ctrl-C
            if (error.empty()) {
                print_message(stderr,
                              "gaitlab: the script has finished; the viewer still serves %s "
                              "(Ctrl-C quits)\n",
                              view->url().c_str());
                view->message("info",
                              "the script has finished: play on, or quit with Ctrl-C "
                              "in the terminal");
            } else {
                report_line(error);
                print_message(stderr,
                              "gaitlab: the script failed; the viewer still serves %s (Ctrl-C "
                              "quits)\n",
                              view->url().c_str());
                view->message("error", "the script failed: " + error);
            }
            view->serve([] { return g_signal != 0; }, error);
            // what was recorded after the script is part of the run: it ends as the script did
            if (g_signal == SIGINT || g_signal == SIGTERM || g_signal == SIGHUP) {
                quit_viewer = true;
                host.clear_interrupt();
            }
        }
        host.set_view_handler({});
        view.reset();
        // sim:play() plays in the console, between keystrokes: a script has no such time
        if (const int n = host.playing(); n > 0 && error.empty() && !a.view) {
            print_message(stderr,
                          "note: %d simulation%s left playing when the script ended: simulations "
                          "play in the console (gaitlab -i %s)\n",
                          n, n == 1 ? " was" : "s were", a.file.c_str());
        }
        // the run folders keep the reason ("interrupted" with the signal, "failed" with the
        // error); a failed close must not hide the error
        try {
            host.finish(error);
        } catch (const std::exception& e) {
            if (error.empty()) error = e.what();
        }
        folders = host.run_folders();
    } catch (const std::exception& e) {
        if (error.empty()) error = e.what();
    }
    if (g_signal != 0 && !quit_viewer) {
        // a broken pipe ends quietly, as SIGPIPE would have
        if (g_signal != SIGPIPE) {
            report_line(error.empty() ? "interrupted" : error);
        }
        return 128 + g_signal;
    }
    if (!error.empty()) {
        // the viewer showed it already
        if (!quit_viewer) report_line(error);
        return 1;
    }
    // one line saying where the runs went
    if (folders.size() == 1) {
        print_message(stderr, "recorded %s\n", folders[0].c_str());
    } else if (!folders.empty()) {
        std::string list;
        for (const std::string& f : folders)
            list += (list.empty() ? "" : ", ") + f;
        print_message(stderr, "recorded %zu runs: %s\n", folders.size(), list.c_str());
    }
    return 0;
}

// ---------------------------------------------------------------------------------------------
// gaitlab data

struct DataArgs {
    std::string dir;
    bool list = false;
    bool events = false;
    std::vector<std::string> series;
    std::string csv;
    std::string split;
    std::string plot;
    std::vector<std::string> xy;  // --xy X Y: a path plot
    std::string title;
    std::string from, to;
    bool has_from = false, has_to = false;
};

// "a,b,c" and repeated --series options: one list
std::vector<std::string> split_names(const std::vector<std::string>& given) {
    std::vector<std::string> out;
    for (const std::string& g : given) {
        size_t start = 0;
        for (;;) {
            const size_t comma = g.find(',', start);
            const std::string n =
                g.substr(start, comma == std::string::npos ? comma : comma - start);
            if (!n.empty()) out.push_back(n);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    }
    return out;
}

// a time for people, with as many decimals as the time step has (dt 0.001: "50.73", where the
// tick times in data.csv read 50.730000000000004); the CSV output keeps every digit
std::string seconds_text(double t, double dt) {
    int decimals = 0;
    for (; decimals < 17; ++decimals) {
        const std::string d = fmt::format("{:.{}f}", dt, decimals);
        double back = 0;
        std::from_chars(d.data(), d.data() + d.size(), back);
        if (back == dt) break;
    }
    std::string s = fmt::format("{:.{}f}", t, decimals);
    if (s.find('.') != std::string::npos) {
        s.erase(s.find_last_not_of('0') + 1);
        if (s.back() == '.') s.pop_back();
    }
    return s == "-0" ? "0" : s;
}

void print_summary(const gaitlab::RunData& run) {
    const gaitlab::RunMeta& m = run.meta();
    const std::vector<double> t = run.times();
    Stdout::print("run      {}\n", terminal_line(run.dir()));
    Stdout::print("status   {}\n", terminal_line(run.state()));
    if (!m.script.empty())
        Stdout::print("script   {} (seed {})\n", terminal_line(m.script), m.script_seed);
    Stdout::print("started  {}\n", terminal_line(m.started));
    // the gaitlab that recorded it: run folders written before it kept its commit say less
    std::string built, commit;
    for (const auto& [key, value] : m.provenance) {
        if (key == "gaitlab") built = value;
        if (key == "commit") commit = value;
    }
    if (!built.empty() || !commit.empty()) {
        Stdout::print("gaitlab  {}{}\n", built.empty() ? "?" : terminal_line(built),
                      commit.empty() ? "" : fmt::format(" (commit {})", terminal_line(commit)));
    }
    Stdout::print("rows     {}{}, t = {} .. {} s, every {} ticks of {} s\n", t.size(),
                  run.truncated() ? " (last line cut short, dropped)" : "",
                  t.empty() ? "-" : seconds_text(t.front(), m.options.dt),
                  t.empty() ? "-" : seconds_text(t.back(), m.options.dt), m.record_every,
                  m.options.dt);
    Stdout::print("series   {} (gaitlab data {} --list)\n", run.series().size(),
                  terminal_line(run.dir()));
    Stdout::print("events   {}\n", run.events().size());
}

int data_command(const DataArgs& a) {
    const double from = a.has_from ? parse_seconds("--from", a.from) : -gaitlab::RunData::kInf;
    const double to = a.has_to ? parse_seconds("--to", a.to) : gaitlab::RunData::kInf;
    if (from > to) {
        throw gaitlab::SpecError(
            fmt::format("--from {} is after --to {}: no row can be in between", a.from, a.to));
    }
    const std::vector<std::string> wanted = split_names(a.series);
    if (!a.series.empty() && wanted.empty()) {
        throw gaitlab::SpecError("--series: at least one series name expected");
    }
    const gaitlab::RunData run(a.dir);
    if (a.list) {
        std::vector<std::string> names = wanted.empty() ? run.names() : run.select(wanted);
        size_t width = 4;
        for (const std::string& n : names)
            width = std::max(width, terminal_line(n).size());
        Stdout::print("{:<{}}  {:<10}  {:<5}  {}\n", "name", width, "kind", "joint", "unit");
        for (const std::string& n : names) {
            const gaitlab::SeriesInfo& s = run.find(n);
            if (!Stdout::print("{:<{}}  {:<10}  {:<5}  {}\n", terminal_line(s.name), width,
                               gaitlab::to_string(s.kind),
                               s.joint > 0 ? std::to_string(s.joint) : "", terminal_line(s.unit)))
                break;
        }
        return 0;
    }
    if (a.events) {
        const std::vector<gaitlab::Event> events = run.events();  // all read, or an error
        Stdout::write("tick,time,origin,kind,name,value,detail\n");
        for (const gaitlab::Event& e : events) {
            if (!Stdout::print("{},{},{},{},{},{},{}\n", e.tick,
                               static_cast<double>(e.tick) * run.meta().options.dt,
                               gaitlab::to_string(e.origin), gaitlab::to_string(e.kind),
                               csv_field(e.name), e.value, csv_field(e.detail)))
                break;
        }
        return 0;
    }
    if (!a.xy.empty()) {
        if (a.plot.empty()) throw gaitlab::SpecError("--xy needs --plot OUT.png");
        if (a.xy[0].empty() || a.xy[1].empty()) {
            throw gaitlab::SpecError("--xy: two series names expected (X and Y)");
        }
        if (!a.series.empty()) {
            throw gaitlab::SpecError(
                "--xy plots one series against another: give no --series with it");
        }
    }
    if (!a.plot.empty()) {
        if (wanted.empty() && a.xy.empty()) {
            throw gaitlab::SpecError("--plot needs --series NAME[,NAME...] or --xy X Y");
        }
        gaitlab::PlotOptions o;
        o.output = a.plot;
        o.series = wanted;
        if (!a.xy.empty()) {
            o.x = a.xy[0];
            o.y = a.xy[1];
        }
        o.from = from;
        o.to = to;
        o.title = a.title;
        const gaitlab::PlotFiles f = gaitlab::plot(run, o);
        Stdout::print("wrote {} (gnuplot script {}, data {})\n", terminal_line(f.png),
                      terminal_line(f.script), terminal_line(f.data));
        return 0;
    }
    if (!wanted.empty()) {
        const std::vector<std::string> names = run.select(wanted);
        if (!a.split.empty()) {
            for (const std::string& path : run.write_split(a.split, names, from, to)) {
                if (!Stdout::print("wrote {}\n", terminal_line(path))) break;
            }
            return 0;
        }
        if (!a.csv.empty()) {
            run.write_csv(a.csv, names, from, to);
            return 0;
        }
        // to stdout: the same CSV, written as it is made (a closed stdout stops it)
        const std::vector<gaitlab::SeriesData> d = run.get(names, from, to);
        std::string out = "time";
        for (const std::string& n : names)
            out += "," + csv_field(n);
        out += "\n";
        for (size_t i = 0; i < (d.empty() ? 0 : d[0].time.size()); ++i) {
            out += fmt::format("{}", d[0].time[i]);
            for (const gaitlab::SeriesData& s : d)
                out += fmt::format(",{}", s.values[i]);
            out += "\n";
            if (out.size() >= (1 << 16)) {
                if (!Stdout::write(out)) return 0;
                out.clear();
            }
        }
        Stdout::write(out);
        return 0;
    }
    if (!a.csv.empty() || !a.split.empty()) {
        throw gaitlab::SpecError("--csv and --split need --series NAME[,NAME...]");
    }
    print_summary(run);
    return 0;
}

// ---------------------------------------------------------------------------------------------
// gaitlab replay

int replay_command(const std::string& dir, const std::string& into) {
    // a signal stops the replay as it stops `gaitlab run`: its folder closed as interrupted
    const gaitlab::scripting::ReplayResult r =
        gaitlab::scripting::replay(dir, into, [](gaitlab::scripting::LuaHost* host) {
            g_host.store(host);
            if (host && g_signal != 0) host->interrupt(g_signal);
        });
    if (g_signal != 0) {
        if (g_signal != SIGPIPE)
            print_message(stderr, "gaitlab: interrupted (%s)\n", strsignal_name(g_signal));
        return 128 + g_signal;
    }
    if (!r.script_error.empty()) {
        print_message(stderr, "gaitlab: replay failed: %s\n", r.script_error.c_str());
        return 1;
    }
    if (!r.ok()) {
        // a run that failed: how the replay's failure departs from it comes with the data's
        std::string why = !r.divergence.empty() ? r.divergence : r.comparison.difference;
        if (!r.failure.empty()) why = why.empty() ? r.failure : why + "; " + r.failure;
        print_message(stderr, "gaitlab: replay differs: %s\n", why.c_str());
        return 1;
    }
    const std::string how = !r.run_error.empty()
                                ? fmt::format(" (the run failed the same way at t = {} s: {})",
                                              r.failed_at, terminal_line(r.run_error))
                            : r.stopped_early ? " (up to where the run stopped)"
                                              : "";
    Stdout::print(
        "replay identical: {} rows x {} series, bit for bit{}; {} recorded {} applied (into "
        "{})\n",
        r.comparison.rows, r.comparison.series, how, r.applied,
        r.applied == 1 ? "change" : "changes", terminal_line(r.into));
    return 0;
}

// ---------------------------------------------------------------------------------------------
// gaitlab view

struct ViewArgs {
    std::string dir;
    std::string port;
    std::string host;
    std::string video;  // --video OUT.webm
    std::string speed = "1";
    std::string size = "960x540";
};

int view_command(const ViewArgs& a) {
    gaitlab::viewer::ServerOptions server;
    double speed = 1;
    int width = 0, height = 0;
    try {
        char x = 0, rest = 0;
        if (std::sscanf(a.size.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' ||
            width < 64 || width > 3840 || height < 64 || height > 2160 || width % 2 != 0 ||
            height % 2 != 0) {
            throw gaitlab::SpecError(fmt::format(
                "--size: WIDTHxHEIGHT in pixels expected, even numbers from 64x64 to 3840x2160 "
                "(got '{}')",
                a.size));
        }
        if (!a.port.empty()) server.port = parse_port(a.port);
        if (!a.host.empty()) server.host = a.host;
        // a factor, not seconds: parsed as a number, refused in the factor's words
        try {
            speed = parse_seconds("--speed", a.speed);
        } catch (const gaitlab::SpecError&) {
            speed = 0;
        }
        if (!(speed > 0 && speed <= 100)) {
            throw gaitlab::SpecError(fmt::format(
                "--speed: a real-time factor in (0, 100] expected (got '{}')", a.speed));
        }
    } catch (const gaitlab::Error& e) {
        print_message(stderr, "gaitlab: %s (see 'gaitlab view --help')\n", e.what());
        return 2;
    }
    if (!a.video.empty()) {
        const std::string error = gaitlab::viewer::render_video(
            a.dir, a.video, speed, [] { return g_signal != 0; }, gaitlab::viewer::find_chromium(),
            width, height);
        if (g_signal != 0) {
            print_message(stderr, "gaitlab: interrupted (%s)\n", strsignal_name(g_signal));
            return 128 + g_signal;
        }
        if (!error.empty()) {
            report_line(error);
            return 1;
        }
        print_message(stderr, "wrote %s\n", a.video.c_str());
        return 0;
    }
    std::unique_ptr<gaitlab::viewer::RunView> view;
    try {
        gaitlab::viewer::RunViewOptions options;
        options.cancel = [] { return g_signal != 0; };
        view = std::make_unique<gaitlab::viewer::RunView>(a.dir, server, options);
    } catch (const gaitlab::viewer::ServerError& e) {
        report_line(e.what());
        return 1;
    }
    if (g_signal != 0) {
        print_message(stderr, "gaitlab: interrupted (%s)\n", strsignal_name(g_signal));
        return 128 + g_signal;
    }
    for (const std::string& note : view->notes())
        report_line(note);
    print_message(stderr,
                  "viewer: %s\n  open it in a browser: the recorded run %s (Ctrl-C quits)\n",
                  view->url().c_str(), a.dir.c_str());
    if (server.host == "0.0.0.0" || server.host == "::") {
        print_message(stderr,
                      "  from another machine: this machine's address in place of 127.0.0.1, "
                      "with the token\n");
    }
    view->serve([] { return g_signal != 0; });
    return 0;
}

// ---------------------------------------------------------------------------------------------
// the command line

// what the user typed that no part of the command line took, as one line: unknown options
// (with the closest option of the command they were given to) and arguments no command takes
std::string leftover_error(CLI::App& app) {
    std::vector<const CLI::App*> apps{&app};
    for (const CLI::App* sub : app.get_subcommands())
        apps.push_back(sub);
    for (const CLI::App* a : apps) {
        const bool top = a == &app;
        const std::string command = top ? "gaitlab" : "gaitlab " + a->get_name();
        const std::string see = fmt::format("see '{} --help'", command);
        for (const std::string& arg : a->remaining()) {
            if (arg == "--") continue;
            if (arg.size() < 2 || arg[0] != '-') {
                if (top) {
                    std::vector<std::string> commands;
                    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
                        commands.push_back(sub->get_name());
                    return fmt::format("unknown command '{}'{} ({})", arg,
                                       gaitlab::did_you_mean(arg, commands), see);
                }
                return fmt::format("unexpected argument '{}' for '{}' ({})", arg, command, see);
            }
            // the option as typed, without "=VALUE"
            const std::string name = arg.substr(0, arg.find('='));
            std::vector<std::string> options{"--help"};
            if (top) options.emplace_back("--version");
            for (const CLI::Option* o : a->get_options()) {
                for (const std::string& l : o->get_lnames())
                    options.push_back("--" + l);
            }
            const std::string suggestion = gaitlab::did_you_mean(name, options);
            const std::string where = top ? "" : fmt::format(" for '{}'", command);
            if (suggestion.empty() && a->get_name() == "run") {
                return fmt::format(
                    "unknown option '{}'{} (the script's arguments go after FILE, and after '--' "
                    "when one starts with '-'; {})",
                    name, where, see);
            }
            return fmt::format("unknown option '{}'{}{} ({})", name, where, suggestion, see);
        }
    }
    return "";
}

}  // namespace

int main(int argc, char** argv) {
    keep_standard_streams();
    // a file size limit ends a write with an error (reported, data kept), not the process
    std::signal(SIGXFSZ, SIG_IGN);
    // a reader that went away makes writes fail (EPIPE), checked like any other failure;
    // `gaitlab run` handles the signal below, so its run folders close first
    std::signal(SIGPIPE, SIG_IGN);
    std::vector<std::string> argl(argv + 1, argv + argc);
    // "gaitlab FILE.lua ..." is "gaitlab run FILE.lua ..." (and FILE.xml)
    if (!argl.empty() && (ends_with(argl[0], ".lua") || ends_with(argl[0], ".xml"))) {
        argl.insert(argl.begin(), "run");
    }
    // "gaitlab -i FILE.lua ..." is "gaitlab console FILE.lua ..."
    if (!argl.empty() && argl[0] == "-i") argl[0] = "console";
    std::string command = "gaitlab";
    for (const std::string& a : argl)
        command += " " + a;
    // everything after the first "--" of `gaitlab run` is the script's, as it is
    std::vector<std::string> script_tail;
    if (!argl.empty() && (argl[0] == "run" || argl[0] == "console")) {
        const auto dash = std::find(argl.begin(), argl.end(), "--");
        if (dash != argl.end()) {
            script_tail.assign(dash + 1, argl.end());
            argl.erase(dash, argl.end());
        }
    }

    CLI::App app{"gaitlab: simulate modular robots and their locomotion controllers", "gaitlab"};
    app.set_version_flag("--version", std::string("gaitlab ") + gaitlab::version());
    app.require_subcommand(0, 1);
    // what CLI11 does not take is checked below, with suggestions
    app.allow_extras();

    RunArgs ra;
    CLI::App* run = app.add_subcommand(
        "run", "Run a Lua script, or a simulation file, headless (recorded to runs/)");
    run->allow_extras();
    // FILE may also be the first argument after "--" (checked below)
    run->add_option("file", ra.file, "The script (FILE.lua) or simulation file (FILE.xml)");
    run->add_option("args", ra.args,
                    "Arguments for the script: arg[1], arg[2], ... (after '--' when one starts "
                    "with '-')")
        ->type_name("ARGS");
    run->add_option("--seed", ra.seed,
                    "Seed for everything random (math.random too): 0 to 2^64 - 1")
        ->type_name("N")
        ->capture_default_str();
    auto* record = run->add_option("--record", ra.record,
                                   "Record into DIR (default: runs/NAME-DATE-TIME; more "
                                   "simulations: DIR-2, DIR-3, ...)");
    record->type_name("DIR");
    auto* no_record =
        run->add_flag("--no-record", ra.no_record, "Record nothing, whatever the script asks");
    record->excludes(no_record);
    run->add_flag("--no-progress", ra.no_progress,
                  "No progress line for long runs (shown on stderr when it is a terminal)");
    auto* view = run->add_flag("--view", ra.view,
                               "Watch and steer it in a browser: serves a page on "
                               "http://127.0.0.1:PORT (see docs/viewer.md)");
    run->add_option("--port", ra.port, "With --view: the port (default: any free port)")
        ->type_name("P")
        ->needs(view);
    run->add_option("--host", ra.host,
                    "With --view: the address to listen on (default 127.0.0.1, this machine "
                    "only; any other needs the token of the printed address)")
        ->type_name("ADDR")
        ->needs(view);
    run->footer(
        "Arguments after FILE go to the script as arg[1], arg[2], ...; gaitlab's own options may\n"
        "stand anywhere, any other option is an error: put '--' before the script's arguments\n"
        "when one starts with '-' (gaitlab run walk.lua -- --speed 2).\n"
        "Each simulation the script creates is recorded into a run folder of its own (data.csv,\n"
        "series.csv, events.csv, log.txt, run.json, config/), written every 2 s of wall time;\n"
        "SIGINT, SIGTERM or SIGHUP close the folders as interrupted (exit status 128 + the\n"
        "signal). See docs/data.md.\n"
        "With --view, sim:run plays at real time in the page (speed, pause, step, reset and\n"
        "the controllers' parameters there), starting when the page opens; after the script\n"
        "the page still serves until Ctrl-C. See docs/viewer.md.");

    CheckArgs cka;
    CLI::App* check = app.add_subcommand(
        "check",
        "Check that a simulation file's result does not depend on dt or the solver iterations");
    check->allow_extras();
    check->add_option("file", cka.file, "The simulation file (FILE.xml)")
        ->required()
        ->type_name("FILE.xml");
    check
        ->add_option("--seconds", cka.seconds,
                     "How long each run is (default: the file's duration)")
        ->type_name("S");
    check
        ->add_option("--cycle", cka.cycle,
                     "Seconds between the samples of each robot's path: the gait's cycle "
                     "(default 1)")
        ->type_name("C");
    check
        ->add_option("--settle", cka.settle,
                     "Seconds left out at the start, before the first sample (default 0)")
        ->type_name("T");
    check->footer(
        "Runs the file's world three times from time 0, recording nothing: at its settings, at\n"
        "dt / 4 (control_every x 4, the same control period) and with 4x the solver iterations;\n"
        "prints each robot's path (its centre of mass on the floor, sampled once per cycle) in\n"
        "each run, and a warning naming each setting that changes a path by more than 3 %.\n"
        "Exit status 0: within 3 %; 3: a setting was warned; 1 or 2: an error. It costs about\n"
        "6-8 runs of S seconds. See docs/performance.md, \"The accuracy check\".");

    gaitlab::cli::ConsoleArgs ca;
    CLI::App* console = gaitlab::cli::add_console_command(app, ca);

    DataArgs da;
    CLI::App* data = app.add_subcommand("data", "List, extract, export or plot recorded series");
    data->allow_extras();
    data->add_option("dir", da.dir, "A run folder")->required()->type_name("DIR");
    auto* list = data->add_flag("--list", da.list, "List the series (name, kind, joint, unit)");
    auto* events = data->add_flag("--events", da.events, "Print the recorded changes as CSV");
    auto* series =
        data->add_option("--series", da.series,
                         "Series to extract, export or plot: names, kinds (robot, controller, "
                         "sensor) or patterns with *, comma-separated")
            ->type_name("NAME[,NAME...]");
    auto* csv = data->add_option("--csv", da.csv, "Write time and the series to this CSV file")
                    ->type_name("OUT.csv");
    auto* split = data->add_option("--split", da.split, "Write each series to its own DIR/NAME.csv")
                      ->type_name("DIR");
    auto* plot =
        data->add_option("--plot", da.plot,
                         "Plot the series into a PNG (gnuplot); OUT.gp and OUT.csv stay next to it")
            ->type_name("OUT.png");
    data->add_option("--xy", da.xy,
                     "With --plot: series Y against series X, one scale (a path from above: "
                     "--xy snake.com.x snake.com.y)")
        ->expected(2)
        ->type_name("X Y");
    data->add_option("--title", da.title, "Title of the plot (default: the run's name)");
    auto* from =
        data->add_option("--from", da.from, "Only rows at or after this time, s")->type_name("T");
    auto* to =
        data->add_option("--to", da.to, "Only rows at or before this time, s")->type_name("T");
    events->excludes(list)->excludes(series);
    csv->excludes(split)->excludes(plot);
    split->excludes(plot);
    data->footer(
        "Without an option: a summary of the run. With --series only: the series as CSV on "
        "stdout.\nA last line cut short (a killed run) is ignored.");

    std::string replay_dir, replay_into;
    CLI::App* replay = app.add_subcommand(
        "replay",
        "Rerun a recorded run headless and check that it reproduces the data bit for "
        "bit");
    replay->allow_extras();
    replay->add_option("dir", replay_dir, "The run folder")->required()->type_name("DIR");
    replay->add_option("--into", replay_into, "Record the replay here (default: DIR-replay)")
        ->type_name("DIR");
    replay->footer(
        "The replay runs the script and controller files copied into DIR/config with the "
        "run's\nseed and arguments, and applies the changes the run recorded from the console, "
        "the viewer\nor reloads from disk at their ticks. Exit status 0: identical. It runs "
        "the run's script:\nreplay only runs you trust.");

    ViewArgs va;
    CLI::App* view_app = app.add_subcommand(
        "view", "Watch a recorded run in a browser: play it back, plot and export its series");
    view_app->allow_extras();
    view_app->add_option("dir", va.dir, "The run folder")->required()->type_name("DIR");
    auto* view_port = view_app->add_option("--port", va.port, "The port (default: any free port)")
                          ->type_name("P");
    auto* view_host =
        view_app
            ->add_option("--host", va.host,
                         "The address to listen on (default 127.0.0.1, this machine only; any "
                         "other needs the token of the printed address)")
            ->type_name("ADDR");
    auto* video = view_app
                      ->add_option("--video", va.video,
                                   "Render the run to this WebM video in headless chromium "
                                   "(no window), then exit")
                      ->type_name("OUT.webm");
    view_app->add_option("--speed", va.speed, "With --video: the real-time factor of the video")
        ->type_name("X")
        ->needs(video);
    view_app->add_option("--size", va.size, "With --video: its size in pixels (default 960x540)")
        ->type_name("WxH")
        ->needs(video);
    video->excludes(view_port)->excludes(view_host);
    view_app->footer(
        "Serves a page on http://127.0.0.1:PORT that plays the run's bodies back in 3D on a\n"
        "timeline, plots its series and exports them (PNG, CSV). The 3D scene is rebuilt by\n"
        "running the run's script (from DIR/config) up to its first step, recording nothing:\n"
        "view only runs you trust. See docs/viewer.md.");

    gaitlab::cli::NewCommand new_command(app);
    gaitlab::cli::MakeCommand make_command(app);
    gaitlab::cli::OptimizeCommand optimize_command(app);
    gaitlab::cli::SweepCommand sweep_command(app);
    gaitlab::cli::EditCommand edit_command(app);

    std::vector<const char*> args{argv[0]};
    for (const std::string& a : argl)
        args.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(args.size()), args.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {  // --help, --version: to stdout, checked
            std::ostringstream out, err;
            const int status = app.exit(e, out, err);
            Stdout::write(out.str());
            return Stdout::finish(status);
        }
        // a failure is one line on stderr, like every other failure of gaitlab
        // (status 2, a usage error, as for an unknown option; not CLI11's codes 101-127,
        // which shells read as "not found", "killed"...), pointing at the help of the
        // subcommand it was for, in gaitlab's words where CLI11's say little
        std::string help = "gaitlab";
        for (const CLI::App* at = &app; at != nullptr;) {
            const std::vector<CLI::App*> subs = at->get_subcommands();
            at = subs.empty() ? nullptr : subs.front();
            if (at) help += " " + at->get_name();
        }
        help += " --help";
        std::string what = e.what();
        static const std::regex twice(R"(^(\S+): At Most 1 required but received (\d+)$)");
        std::smatch m;
        if (std::regex_match(what, m, twice)) {
            what = m[1].str() + " given " + m[2].str() + " times (give it once)";
        }
        print_message(stderr, "gaitlab: %s (see '%s')\n", what.c_str(), help.c_str());
        return 2;
    }
    if (const std::string error = leftover_error(app); !error.empty()) {
        report_line(error);
        return 2;
    }
    if (*run) {
        if (ra.file.empty() && !script_tail.empty()) {
            ra.file = script_tail.front();
            script_tail.erase(script_tail.begin());
        }
        if (ra.file.empty()) {
            // an empty name given, or the file taken as an option's value (--seed base.lua)
            print_message(stderr, "gaitlab: %s (see 'gaitlab run --help')\n",
                          run->get_option("file")->count() > 0
                              ? "a script or simulation file expected, got an empty name"
                              : "a script or simulation file is required (gaitlab run FILE.lua; "
                                "an option before it takes its value first)");
            return 2;
        }
        ra.args.insert(ra.args.end(), script_tail.begin(), script_tail.end());
        catch_signals();
        return Stdout::finish(run_script(ra, command));
    }
    if (*console || argl.empty()) {
        // `gaitlab -i ""`: a file asked for and none named is no plain console
        if (console->get_option("file")->count() > 0 && ca.file.empty()) {
            print_message(stderr,
                          "gaitlab: a Lua file to run first expected, got an empty name (see "
                          "'gaitlab console --help')\n");
            return 2;
        }
        if (ca.file.empty() && !script_tail.empty()) {
            ca.file = script_tail.front();
            script_tail.erase(script_tail.begin());
        }
        ca.args.insert(ca.args.end(), script_tail.begin(), script_tail.end());
        return Stdout::finish(
            gaitlab::cli::run_console(ca, command, [](gaitlab::scripting::LuaHost& host) {
                host.set_optimize_handler(gaitlab::cli::lua_optimize_handler());
            }));
    }
    da.has_from = from->count() > 0;
    da.has_to = to->count() > 0;
    int status = 0;
    try {
        if (*check) {
            catch_signals();
            status = check_command(cka);
        } else if (*data) {
            status = data_command(da);
        } else if (new_command.chosen()) {
            status = new_command.run();
        } else if (make_command.chosen()) {
            status = make_command.run();
        } else if (optimize_command.chosen()) {
            catch_signals();
            status = optimize_command.run(command);
        } else if (sweep_command.chosen()) {
            catch_signals();
            status = sweep_command.run(command);
        } else if (edit_command.chosen()) {
            status = edit_command.run();
        } else if (*replay) {
            catch_signals();
            status = replay_command(replay_dir, replay_into);
        } else if (*view_app) {
            catch_signals();
            status = view_command(va);
        } else {
            Stdout::write(app.help());
        }
    } catch (const std::exception& e) {
        // messages may quote a run folder's content: no control characters to the terminal
        report_line(e.what());
        status = 1;
    }
    return Stdout::finish(status);
}
