// The console's core: lua.c's interpreter loop (`=expr`, `return <line>` first, continuation
// lines while the chunk is incomplete, errors with a traceback) as a class that is fed lines and
// owns no terminal, so a front end (cli/console_frontend.h) or a test drives it.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace gaitlab::scripting {

class LuaHost;

class Console {
  public:
    /// What feed() did with a line.
    enum class Status {
        ran,       ///< a complete chunk ran (its results or its error were written)
        more,      ///< the chunk is incomplete: feed its next line (prompt ">> ")
        rejected,  ///< a syntax error was written; nothing ran
    };
    /// Where the console writes: results to `out`, errors to `err`; each call gets whole lines
    /// ending with '\n'.
    using Writer = std::function<void(const std::string&)>;

    /// A console running lines in `host` (which must outlive it), writing to stdout and stderr.
    explicit Console(LuaHost& host);

    /// Replaces the writers (empty functions: stdout, stderr).
    void set_writers(Writer out, Writer err);

    /// Feeds one line as typed, without its newline (it may hold any bytes, zeros included).
    /// A complete chunk runs with the host's origin set to "console"; its results are written
    /// pretty-printed (gaitlab.pretty), tab-separated; an error is written with its traceback.
    /// After the line, any interrupt of the host is cleared. Never throws for what the line
    /// holds.
    Status feed(std::string_view line);

    /// "> " or, while a chunk is incomplete, ">> ".
    const char* prompt() const;
    /// Whether a chunk is incomplete (lines fed since the last complete one).
    bool pending() const { return !buffer_.empty(); }
    /// Forgets an incomplete chunk (Ctrl-C at the prompt).
    void discard();
    /// The last chunk that was complete (its lines joined with '\n'), for the history.
    const std::string& last_chunk() const { return last_chunk_; }

    /// Completions for the text before the cursor: the word being typed is the trailing
    /// `name(.name|:name)*` part of `before`; the result replaces it. Globals and keywords for
    /// a first name, table fields after '.', methods after ':' (found through metatables'
    /// __index, gaitlab types' method tables and controllers' parameters), sorted; functions
    /// get "(". Runs no Lua code (no metamethod is called).
    std::vector<std::string> complete(std::string_view before) const;
    /// Where in `before` the word complete() completes starts.
    static std::size_t word_start(std::string_view before);

  private:
    // runs the chunk on top of the stack, writes its results or error
    void run();
    void write_error(const std::string& text) const;

    LuaHost& host_;
    Writer out_, err_;
    std::string buffer_;  // the lines of an incomplete chunk
    std::string last_chunk_;
};

}  // namespace gaitlab::scripting
