#include "console_frontend.h"

#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <histedit.h>

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
#include <stdexcept>
#include <system_error>

#include "gaitlab/terminal.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_prompt_interrupted = 0;

// The terminal side is libedit's own interface (histedit.h), not its readline emulation: the
// emulation's rl_line_buffer keeps pointing at the line's first buffer after libedit has
// reallocated it for a line of more than about a thousand bytes, and every key after that
// wrote into freed memory (a pasted line of 3000 characters aborted the console). Here the
// line is read through el_line each time it is needed, never kept.
EditLine* g_el = nullptr;
History* g_history = nullptr;
const std::string* g_prompt = nullptr;  // the prompt libedit draws
std::function<std::vector<std::string>(std::string_view)>* g_complete = nullptr;
LineInput* g_input = nullptr;  // the terminal LineInput, whose history the process's end saves

extern "C" void save_history_at_exit() {
    if (g_input) g_input->save_history();
}

extern "C" char* prompt_text(EditLine*) {
    return const_cast<char*>(g_prompt ? g_prompt->c_str() : "");
}

// the text of the line being edited, and the cursor's offset in it
std::string line_text(std::size_t* cursor = nullptr) {
    const LineInfo* li = el_line(g_el);
    if (!li || !li->buffer) {
        if (cursor) *cursor = 0;
        return {};
    }
    if (cursor) *cursor = static_cast<std::size_t>(li->cursor - li->buffer);
    return std::string(li->buffer, static_cast<std::size_t>(li->lastchar - li->buffer));
}

double now_seconds() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

size_t terminal_columns();

// Tab: the candidates of the text before the cursor (Options::complete), each replacing the
// trailing word (letters, digits, '_', '.' and ':': robot:gr, gaitlab.sim). One candidate, or
// a longer common beginning, is put in; otherwise the candidates are listed below the line.
extern "C" unsigned char complete_word(EditLine*, int) {
    if (!g_complete || !*g_complete) return CC_ERROR;
    std::size_t cursor = 0;
    const std::string before = line_text(&cursor).substr(0, cursor);
    std::vector<std::string> found;
    try {
        found = (*g_complete)(before);
    } catch (const std::exception&) {
        return CC_ERROR;
    }
    if (found.empty()) return CC_ERROR;
    size_t word = before.size();
    while (word > 0 &&
           (std::isalnum(static_cast<unsigned char>(before[word - 1])) || before[word - 1] == '_' ||
            before[word - 1] == '.' || before[word - 1] == ':'))
        --word;
    const std::string typed = before.substr(word);
    std::string common = found.front();
    for (const std::string& f : found) {
        size_t n = 0;
        while (n < common.size() && n < f.size() && common[n] == f[n])
            ++n;
        common.resize(n);
    }
    if (found.size() == 1 || common.size() > typed.size()) {
        el_deletestr(g_el, static_cast<int>(typed.size()));
        el_insertstr(g_el, (found.size() == 1 ? found.front() : common).c_str());
        return CC_REFRESH;
    }
    // nothing to add: the candidates in columns under the line, then the line again
    size_t width = 0;
    for (const std::string& f : found)
        width = std::max(width, f.size() + 2);
    const size_t per_row = std::max<size_t>(1, terminal_columns() / width);
    std::string list = "\n";
    for (size_t i = 0; i < found.size(); ++i) {
        list += found[i];
        const bool last = (i + 1) % per_row == 0 || i + 1 == found.size();
        list += last ? std::string("\n") : std::string(width - found[i].size(), ' ');
    }
    std::fwrite(list.data(), 1, list.size(), stdout);
    std::fflush(stdout);
    return CC_REDISPLAY;
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
    return 80;
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
    g_complete = &options_.complete;
    g_prompt = &prompt_;
    HistEvent event;
    if (g_el) {  // a terminal LineInput before this one: its editor, with an empty history
        history(g_history, &event, H_CLEAR);
    } else {
        // made once and kept for the process, as libedit's readline emulation keeps its own:
        // el_end would lose the names EL_ADDFN copied (libedit frees its function table but not
        // them), and the terminal is left in its ordinary mode after every line anyway
        g_el = el_init("gaitlab", stdin, stdout, stderr);
        g_history = history_init();
        if (!g_el || !g_history) throw std::runtime_error("cannot start the line editor (libedit)");
        history(g_history, &event, H_SETSIZE, 1000);
        el_set(g_el, EL_HIST, history, g_history);
        el_set(g_el, EL_EDITOR, "emacs");
        // gaitlab's own handlers take the signals (Ctrl-C at the prompt, SIGTERM ...)
        el_set(g_el, EL_SIGNAL, 0);
        el_set(g_el, EL_PROMPT, prompt_text);
        el_set(g_el, EL_ADDFN, "gaitlab-complete", "complete the name before the cursor",
               complete_word);
        el_set(g_el, EL_BIND, "^I", "gaitlab-complete", nullptr);
        // the keys a terminal's Home, End and Delete send, and Ctrl-R searching back
        for (const char* home : {"\\e[1~", "\\e[7~", "\\e[H", "\\eOH"})
            el_set(g_el, EL_BIND, home, "ed-move-to-beg", nullptr);
        for (const char* end : {"\\e[4~", "\\e[8~", "\\e[F", "\\eOF"})
            el_set(g_el, EL_BIND, end, "ed-move-to-end", nullptr);
        el_set(g_el, EL_BIND, "\\e[3~", "ed-delete-next-char", nullptr);
        el_set(g_el, EL_BIND, "^R", "em-inc-search-prev", nullptr);
        el_source(g_el, nullptr);  // the user's ~/.editrc (lines for all programs or "gaitlab:")
    }
    termios tty{};
    if (::tcgetattr(0, &tty) == 0 && tty.c_cc[VEOF] != 0)
        eof_char_ = static_cast<char>(tty.c_cc[VEOF]);
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
        const int r = history(g_history, &event, H_LOAD, options_.history_file.c_str());
        // a first session has no history yet
        const bool missing = ::access(options_.history_file.c_str(), F_OK) != 0;
        if (r == -1 && !missing && options_.warn) {
            options_.warn("cannot read the history " + options_.history_file + ": " +
                          std::strerror(errno ? errno : EIO));
        }
        history_ok_ = true;
        g_input = this;
        static const bool registered = std::atexit(save_history_at_exit) == 0;
        (void)registered;
    }
}

LineInput::~LineInput() {
    if (!options_.terminal) return;
    if (prompting_) el_set(g_el, EL_UNBUFFERED, 0);
    save_history();
    g_input = nullptr;
    g_complete = nullptr;
    g_prompt = nullptr;
}

void LineInput::save_history() {
    if (!history_ok_) return;
    errno = 0;
    HistEvent event;
    if (history(g_history, &event, H_SAVE, options_.history_file.c_str()) == -1 && options_.warn) {
        options_.warn("cannot write the history " + options_.history_file + ": " +
                      std::strerror(errno ? errno : EIO));
    }
}

void LineInput::add_history(const std::string& entry) {
    if (!options_.terminal || entry.empty()) return;
    // a NUL would cut the entry: libedit keeps C strings
    HistEvent event;
    history(g_history, &event, H_ENTER, entry.substr(0, entry.find('\0')).c_str());
}

int LineInput::idle_wait() {
    if (!options_.idle) return -1;
    double now = now_seconds();
    if (now >= next_idle_) {
        double wait = 1.0;
        try {
            wait = options_.idle();
        } catch (const std::exception& e) {
            write(stderr, terminal_text(std::string("gaitlab: ") + e.what() + "\n"));
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
    g_prompt_interrupted = 0;
    prompt_ = prompt;
    // a key at a time (el_gets returns after each), the terminal in raw mode, the prompt drawn
    el_set(g_el, EL_UNBUFFERED, 1);
    prompting_ = true;
    // the terminal back as it was (cooked) while the line runs
    const auto done = [this] {
        el_set(g_el, EL_UNBUFFERED, 0);
        prompting_ = false;
    };
    for (;;) {
        if (g_prompt_interrupted) {
            g_prompt_interrupted = 0;
            // what was typed stays on the screen, ended by ^C, and goes (the next prompt starts
            // an empty line)
            done();
            std::fputs("^C\n", stdout);
            std::fflush(stdout);
            return {Line::Kind::interrupted, {}};
        }
        pollfd p{0, POLLIN, 0};
        const int r = ::poll(&p, 1, idle_wait());
        if (r < 0 && errno != EINTR) {
            done();
            return {Line::Kind::end, {}};
        }
        if (r <= 0) continue;
        if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
            // the terminal went away
            done();
            return {Line::Kind::end, {}};
        }
        int count = 0;
        const char* got = el_gets(g_el, &count);
        if (!got) continue;  // the line is empty (a key deleted the last character)
        // el_gets hands over the line so far after every key: a line is complete when it ends
        // in a newline; the terminal's end-of-file character alone is Ctrl-D at an empty prompt
        const std::string_view line(got, static_cast<size_t>(std::max(count, 0)));
        const bool complete = !line.empty() && (line.back() == '\n' || line.back() == '\r');
        const bool eof = line.size() == 1 && line[0] == eof_char_;
        if (!complete && !eof) continue;
        std::string text(line.substr(0, complete ? line.size() - 1 : 0));
        done();
        if (complete) return {Line::Kind::text, std::move(text)};
        std::fputs("\n", stdout);
        std::fflush(stdout);
        return {Line::Kind::end, {}};
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
    size_t point = 0;
    const std::string typed = line_text(&point);
    const size_t before = display_columns(prompt_, 0);
    const size_t at = before + display_columns(std::string_view(typed).substr(0, point), before);
    const size_t row = at / terminal_columns();
    std::fflush(stdout);
    std::fputs("\r", stdout);
    if (row > 0) std::fprintf(stdout, "\033[%zuA", row);
    std::fputs("\033[J", stdout);
    std::fflush(stdout);
    std::fwrite(text.data(), 1, text.size(), stream);
    if (!text.empty() && text.back() != '\n') std::fputc('\n', stream);
    std::fflush(stream);
    el_set(g_el, EL_REFRESH);
}

}  // namespace gaitlab::cli
