// The command line's shared progress pieces (see progress.h).
#include "progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/terminal.h"

namespace gaitlab::cli {

namespace {

std::atomic<int> g_stop{0};
static_assert(std::atomic<int>::is_always_lock_free);

}  // namespace

const std::atomic<int>& evaluations_stop() {
    return g_stop;
}

void stop_evaluations(int signal) {
    int expected = 0;
    g_stop.compare_exchange_strong(expected, signal);
}

std::string default_results_folder(const std::string& kind, const std::string& spec) {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    localtime_r(&now, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    return fmt::format("runs/{}-{}-{}", kind, std::filesystem::path(spec).stem().string(), stamp);
}

std::string duration_text(double s) {
    if (!(s >= 1)) return "<1 s";
    const long n = std::lround(s);
    if (n < 60) return fmt::format("{} s", n);
    if (n < 3600) return fmt::format("{} min {:02} s", n / 60, n % 60);
    return fmt::format("{} h {:02} min", n / 3600, n % 3600 / 60);
}

std::string fitness_text(double v) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string("none");
}

std::string point_text(const optimize::Spec& spec, const std::vector<double>& x) {
    std::string text;
    for (std::size_t i = 0; i < x.size(); ++i) {
        text += fmt::format("{}{} = {}", i == 0 ? "" : ", ", spec.parameters[i].name,
                            fitness_text(x[i]));
    }
    return text;
}

void print_best_simulation(const std::string& file, const std::string& error) {
    if (!file.empty()) {
        print_message(stdout, "the best as a simulation file: gaitlab run %s\n", file.c_str());
    } else {
        print_message(stdout, "the best could not be saved as a simulation file: %s\n",
                      error.c_str());
    }
}

ProgressLine::ProgressLine()
    : terminal_(::isatty(STDERR_FILENO) == 1),
      last_(std::chrono::steady_clock::now() - std::chrono::seconds(1)) {}

ProgressLine::~ProgressLine() {
    clear();
}

void ProgressLine::show(std::string line, bool now) {
    if (!terminal_) return;
    const auto t = std::chrono::steady_clock::now();
    if (t - last_ < std::chrono::milliseconds(200) && !now) return;
    last_ = t;
    winsize ws{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 1 && line.size() >= ws.ws_col) {
        line.resize(ws.ws_col - 1U);
    }
    std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
    std::fflush(stderr);
    shown_ = true;
}

void ProgressLine::clear() {
    if (!shown_) return;
    std::fputs("\r\x1b[K", stderr);
    std::fflush(stderr);
    shown_ = false;
}

}  // namespace gaitlab::cli
