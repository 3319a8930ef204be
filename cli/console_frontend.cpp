#include "console_frontend.h"

#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <editline/readline.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_prompt_interrupted = 0;

// the LineInput libedit works for (its readline interface keeps global state)
LineInput* g_terminal = nullptr;
std::function<std::vector<std::string>(std::string_view)>* g_complete = nullptr;

// the line libedit handed over, and whether it did
struct Handed {
    bool done = false;
    bool eof = false;
    std::string text;
} g_handed;

extern "C" void on_line(char* line) {
    g_handed.done = true;
    g_handed.eof = line == nullptr;
    if (line) {
        g_handed.text = line;
        std::free(line);
    }
    // no prompt while the line runs: libedit gives the terminal back (cooked mode)
    rl_callback_handler_remove();
}

double now_seconds() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

char* dup(const std::string& s) {
    char* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (p) std::memcpy(p, s.c_str(), s.size() + 1);
    return p;
}

// libedit's completion: the candidates of the text before the cursor, as readline wants them
// ([0] what replaces the word: their longest common prefix, then each candidate, then NULL)
extern "C" char** attempt_completion(const char* text, int start, int end) {
    rl_attempted_completion_over = 1;  // never file names
    rl_completion_append_character = '\0';
    if (!g_complete || !*g_complete || end < start) return nullptr;
    const std::string before(rl_line_buffer, static_cast<size_t>(end));
    std::vector<std::string> found;
    try {
        found = (*g_complete)(before);
    } catch (const std::exception&) {
        return nullptr;
    }
    // the candidates replace the word complete() saw; libedit replaces `text`
    (void)text;
    const size_t ws = static_cast<size_t>(start);
    size_t ours = before.size();
    while (ours > 0 &&
           (std::isalnum(static_cast<unsigned char>(before[ours - 1])) || before[ours - 1] == '_' ||
            before[ours - 1] == '.' || before[ours - 1] == ':'))
        --ours;
    std::vector<std::string> matches;
    for (const std::string& f : found) {
        if (ours >= ws) {
            matches.push_back(before.substr(ws, ours - ws) + f);
        } else if (f.size() >= ws - ours) {
            matches.push_back(f.substr(ws - ours));
        }
    }
    if (matches.empty()) return nullptr;
    std::string common = matches.front();
    for (const std::string& m : matches) {
        size_t n = 0;
        while (n < common.size() && n < m.size() && common[n] == m[n])
            ++n;
        common.resize(n);
    }
    char** out = static_cast<char**>(std::calloc(matches.size() + 2, sizeof(char*)));
    if (!out) return nullptr;
    out[0] = dup(matches.size() == 1 ? matches.front() : common);
    for (size_t i = 0; i < matches.size() && matches.size() > 1; ++i)
        out[i + 1] = dup(matches[i]);
    return out;
}

// columns `text` takes on the screen as libedit draws it: UTF-8 sequences one, control
// characters two (^X), tabs to the next multiple of 8 from `column`
size_t display_columns(std::string_view text, size_t column) {
    size_t c = column;
    for (const char ch : text) {
        const auto u = static_cast<unsigned char>(ch);
        if ((u & 0xC0) == 0x80) continue;  // a continuation byte
        if (u == '\t') {
            c += 8 - c % 8;
        } else if (u < 0x20 || u == 0x7F) {
            c += 2;
        } else {
            ++c;
        }
    }
    return c - column;
}

// the terminal's width in columns (80 when it cannot be told)
size_t terminal_columns() {
    winsize ws{};
    if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
    int rows = 0;
    int cols = 0;
    rl_get_screen_size(&rows, &cols);
    return cols > 0 ? static_cast<size_t>(cols) : 80;
}

}  // namespace

std::string default_history_file() {
    const char* state = std::getenv("XDG_STATE_HOME");
    if (state && *state) return (fs::path(state) / "gaitlab" / "history").string();
    const char* home = std::getenv("HOME");
    if (home && *home)
        return (fs::path(home) / ".local" / "state" / "gaitlab" / "history").string();
    return "";
}

void LineInput::interrupt_prompt() {
    g_prompt_interrupted = 1;
}

LineInput::LineInput(Options options) : options_(std::move(options)) {
    next_idle_ = now_seconds();
    if (!options_.terminal) return;
    g_terminal = this;
    g_complete = &options_.complete;
    // gaitlab's own handlers take the signals (Ctrl-C at the prompt, SIGTERM ...)
    rl_catch_signals = 0;
    rl_readline_name = "gaitlab";
    // '.' and ':' are part of the word completed (robot:gr, gaitlab.sim)
    static char breaks[] = " \t\n\"\\'`@$><=;|&{(,+-*/%^~#[])}";
    rl_basic_word_break_characters = breaks;
    rl_completer_word_break_characters = breaks;
    rl_attempted_completion_function = attempt_completion;
    rl_initialize();
    using_history();
    stifle_history(1000);
    if (!options_.history_file.empty()) {
        std::error_code ec;
        fs::create_directories(fs::path(options_.history_file).parent_path(), ec);
        if (ec) {
            if (options_.warn)
                options_.warn("cannot keep the history in " + options_.history_file + ": " +
                              ec.message());
            return;
        }
        errno = 0;
        const int r = read_history(options_.history_file.c_str());
        // a first session has no history yet
        const bool missing = ::access(options_.history_file.c_str(), F_OK) != 0;
        if (r != 0 && !missing && options_.warn) {
            options_.warn("cannot read the history " + options_.history_file + ": " +
                          std::strerror(r > 0 ? r : (errno ? errno : EIO)));
        }
        history_ok_ = true;
    }
}

LineInput::~LineInput() {
    if (!options_.terminal) return;
    if (prompting_) rl_callback_handler_remove();
    save_history();
    g_terminal = nullptr;
    g_complete = nullptr;
}

void LineInput::save_history() {
    if (!history_ok_) return;
    errno = 0;
    const int r = write_history(options_.history_file.c_str());
    if (r != 0 && options_.warn) {
        options_.warn("cannot write the history " + options_.history_file + ": " +
                      std::strerror(r > 0 ? r : (errno ? errno : EIO)));
    }
}

void LineInput::add_history(const std::string& entry) {
    if (!options_.terminal || entry.empty()) return;
    // a NUL would cut the entry: libedit keeps C strings
    ::add_history(entry.substr(0, entry.find('\0')).c_str());
}

int LineInput::idle_wait() {
    if (!options_.idle) return -1;
    double now = now_seconds();
    if (now >= next_idle_) {
        double wait = 1.0;
        try {
            wait = options_.idle();
        } catch (const std::exception& e) {
            write(stderr, std::string("gaitlab: ") + e.what() + "\n");
        }
        if (std::isnan(wait) || wait < 0) wait = 0;
        now = now_seconds();
        if (std::isinf(wait)) {
            next_idle_ = INFINITY;
            return -1;
        }
        next_idle_ = now + wait;
    }
    if (std::isinf(next_idle_)) return -1;
    const double ms = std::ceil((next_idle_ - now) * 1000.0);
    return static_cast<int>(std::clamp(ms, 0.0, static_cast<double>(INT_MAX)));
}

LineInput::Line LineInput::read(const char* prompt) {
    // the hook is due again whenever the console waits for a line
    next_idle_ = now_seconds();
    return options_.terminal ? read_terminal(prompt) : read_plain();
}

LineInput::Line LineInput::read_plain() {
    for (;;) {
        const size_t eol = pending_.find('\n');
        if (eol != std::string::npos) {
            Line l{Line::Kind::text, pending_.substr(0, eol)};
            pending_.erase(0, eol + 1);
            return l;
        }
        if (g_prompt_interrupted) {
            g_prompt_interrupted = 0;
            pending_.clear();
            return {Line::Kind::interrupted, {}};
        }
        if (eof_) {
            if (pending_.empty()) return {Line::Kind::end, {}};
            Line l{Line::Kind::text, std::move(pending_)};
            pending_.clear();
            return l;
        }
        pollfd p{options_.fd, POLLIN, 0};
        const int r = ::poll(&p, 1, idle_wait());
        if (r < 0 && errno != EINTR) {
            eof_ = true;
            continue;
        }
        if (r <= 0) continue;
        char buf[65536];
        const ssize_t n = ::read(options_.fd, buf, sizeof buf);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) {
            eof_ = true;
            continue;
        }
        pending_.append(buf, static_cast<size_t>(n));
    }
}

LineInput::Line LineInput::read_terminal(const char* prompt) {
    g_handed = Handed{};
    g_prompt_interrupted = 0;
    prompt_ = prompt;
    rl_callback_handler_install(prompt, on_line);
    prompting_ = true;
    for (;;) {
        if (g_handed.done) {
            prompting_ = false;
            if (g_handed.eof) {
                // Ctrl-D: leave the prompt's line
                std::fputs("\n", stdout);
                std::fflush(stdout);
                return {Line::Kind::end, {}};
            }
            return {Line::Kind::text, g_handed.text};
        }
        if (g_prompt_interrupted) {
            g_prompt_interrupted = 0;
            // what was typed stays on the screen, ended by ^C, and goes
            rl_replace_line("", 0);
            rl_callback_handler_remove();
            prompting_ = false;
            std::fputs("^C\n", stdout);
            std::fflush(stdout);
            return {Line::Kind::interrupted, {}};
        }
        pollfd p{0, POLLIN, 0};
        const int r = ::poll(&p, 1, idle_wait());
        if (r < 0 && errno != EINTR) {
            rl_callback_handler_remove();
            prompting_ = false;
            return {Line::Kind::end, {}};
        }
        if (r > 0) {
            if (p.revents & POLLIN) {
                rl_callback_read_char();
            } else {
                // the terminal went away (POLLHUP, POLLERR)
                rl_callback_handler_remove();
                prompting_ = false;
                return {Line::Kind::end, {}};
            }
        }
    }
}

void LineInput::write(std::FILE* stream, const std::string& text) {
    if (!prompting_) {
        std::fwrite(text.data(), 1, text.size(), stream);
        std::fflush(stream);
        return;
    }
    // clear the prompt and the typed text from the row where they start (a long line wraps onto
    // several rows, and the cursor is on the row of its position in the text), write there,
    // then draw the prompt and the typed text again below
    const size_t point = rl_line_buffer ? std::min(static_cast<size_t>(std::max(rl_point, 0)),
                                                   std::strlen(rl_line_buffer))
                                        : 0;
    const size_t before = display_columns(prompt_, 0);
    const size_t at =
        before +
        display_columns(std::string_view(rl_line_buffer ? rl_line_buffer : "", point), before);
    const size_t row = at / terminal_columns();
    std::fflush(stdout);
    std::fputs("\r", stdout);
    if (row > 0) std::fprintf(stdout, "\033[%zuA", row);
    std::fputs("\033[J", stdout);
    std::fflush(stdout);
    std::fwrite(text.data(), 1, text.size(), stream);
    if (!text.empty() && text.back() != '\n') std::fputc('\n', stream);
    std::fflush(stream);
    rl_forced_update_display();
}

}  // namespace gaitlab::cli
