// The console's terminal side: reads lines with libedit (line editing, history, completion)
// when stdin is a terminal, plainly otherwise, and never blocks the thread: while it waits for a
// key it calls an idle hook (the host's pump, which steps playing simulations) as often as the
// hook asks.
#pragma once

#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace gaitlab::cli {

class LineInput {
  public:
    struct Options {
        int fd = 0;  ///< where lines come from
        /// libedit line editing (only one LineInput at a time may use it; `fd` must be 0)
        bool terminal = false;
        /// the history file (terminal only; "" : none). Its folders are created; a history
        /// that cannot be read or written is a warning
        std::string history_file;
        /// called while waiting for input; returns the seconds until it must be called again
        /// (+infinity: only when input comes). Its exceptions are written as errors
        std::function<double()> idle;
        /// completions of the text before the cursor, each replacing its trailing word
        /// (gaitlab::scripting::Console::complete)
        std::function<std::vector<std::string>(std::string_view)> complete;
        /// where problems with the history file go (one line without '\n')
        std::function<void(const std::string&)> warn;
    };

    /// What read() got.
    struct Line {
        enum class Kind {
            text,         ///< a line (`text`, without its newline)
            end,          ///< end of input (Ctrl-D at an empty prompt, end of a pipe)
            interrupted,  ///< Ctrl-C at the prompt: the typed text was discarded
        };
        Kind kind = Kind::end;
        std::string text;
    };

    explicit LineInput(Options options);
    /// Saves the history.
    ~LineInput();
    LineInput(const LineInput&) = delete;
    LineInput& operator=(const LineInput&) = delete;

    /// The next line; `prompt` is shown on a terminal only.
    Line read(const char* prompt);
    /// Adds a complete entry (a chunk of one or more lines) to the history.
    void add_history(const std::string& entry);
    /// Writes `text` to `stream`; while a prompt waits (the idle hook printing), the prompt and
    /// the text typed so far are redrawn below it, so the line being typed is not garbled.
    void write(std::FILE* stream, const std::string& text);

    /// Ctrl-C at the prompt: read() returns Kind::interrupted. Async-signal-safe.
    static void interrupt_prompt();

    /// Writes the history file now. The destructor does, and so does the end of the process
    /// while a terminal LineInput lives (os.exit() typed at the console skips destructors).
    void save_history();

  private:
    Line read_plain();
    Line read_terminal(const char* prompt);
    // calls the idle hook if it is due; returns the milliseconds poll may wait
    int idle_wait();

    Options options_;
    std::string pending_;  // bytes read after the last line (plain input)
    bool eof_ = false;
    bool prompting_ = false;  // a libedit prompt is on the screen
    std::string prompt_;      // the prompt on the screen
    double next_idle_ = 0;    // monotonic seconds when the idle hook is due
    bool history_ok_ = false;
    char eof_char_ = '\x04';  // the terminal's end-of-file character (Ctrl-D)
};

/// $XDG_STATE_HOME/gaitlab/history, or ~/.local/state/gaitlab/history ("" when neither
/// XDG_STATE_HOME nor HOME is set).
std::string default_history_file();

}  // namespace gaitlab::cli
