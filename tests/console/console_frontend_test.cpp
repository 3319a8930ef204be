// The console's input side (cli/console_frontend.cpp) reading from a pipe: lines as they come,
// the idle hook called while it waits, Ctrl-C at the prompt, the end of the input.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "console_frontend.h"

using gaitlab::cli::LineInput;
using Kind = LineInput::Line::Kind;

namespace {

struct Pipe {
    int fd[2] = {-1, -1};
    Pipe() { REQUIRE(::pipe(fd) == 0); }
    ~Pipe() {
        for (int f : fd)
            if (f >= 0) ::close(f);
    }
    void write(const std::string& s) const { REQUIRE(::write(fd[1], s.data(), s.size()) == static_cast<ssize_t>(s.size())); }
    void close_writer() {
        ::close(fd[1]);
        fd[1] = -1;
    }
};

}  // namespace

TEST_CASE("lines come as they are written, the last one without its newline", "[frontend]") {
    Pipe p;
    LineInput::Options o;
    o.fd = p.fd[0];
    LineInput in(o);
    p.write("1 + 1\nfor i = 1, 2 do\r\n");
    p.write(std::string("a\0b\nlast", 8));
    p.close_writer();
    CHECK(in.read("> ").text == "1 + 1");
    CHECK(in.read("> ").text == "for i = 1, 2 do\r");
    CHECK(in.read("> ").text == std::string("a\0b", 3));
    const LineInput::Line last = in.read("> ");
    CHECK(last.kind == Kind::text);
    CHECK(last.text == "last");
    CHECK(in.read("> ").kind == Kind::end);
    CHECK(in.read("> ").kind == Kind::end);
}

TEST_CASE("the idle hook runs while the prompt waits, as often as it asks", "[frontend]") {
    Pipe p;
    int calls = 0;
    LineInput::Options o;
    o.fd = p.fd[0];
    o.idle = [&] {
        // the hook is what makes the input come: typing happens while simulations play
        if (++calls == 5) p.write("sim:pause()\n");
        return 0.01;
    };
    LineInput in(o);
    const auto start = std::chrono::steady_clock::now();
    CHECK(in.read("> ").text == "sim:pause()");
    CHECK(calls == 5);
    // it waited between calls as asked (4 waits of 10 ms), without spinning
    CHECK(std::chrono::steady_clock::now() - start >= std::chrono::milliseconds(35));
}

TEST_CASE("an idle hook with nothing to do lets the input block", "[frontend]") {
    Pipe p;
    int calls = 0;
    LineInput::Options o;
    o.fd = p.fd[0];
    o.idle = [&] {
        ++calls;
        return INFINITY;
    };
    LineInput in(o);
    std::thread typist([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(150));
        p.write("x\n");
    });
    CHECK(in.read("> ").text == "x");
    typist.join();
    CHECK(calls == 1);
}

TEST_CASE("a failing idle hook is reported and the input goes on", "[frontend]") {
    Pipe p;
    int calls = 0;
    LineInput::Options o;
    o.fd = p.fd[0];
    o.idle = [&]() -> double {
        if (++calls == 2) p.write("still here\n");
        throw std::runtime_error("pump failed");
    };
    LineInput in(o);
    CHECK(in.read("> ").text == "still here");
    CHECK(calls >= 2);
}

TEST_CASE("Ctrl-C at the prompt discards what was typed", "[frontend]") {
    Pipe p;
    int calls = 0;
    LineInput::Options o;
    o.fd = p.fd[0];
    // Ctrl-C comes while the prompt waits (from the signal handler)
    o.idle = [&] {
        if (++calls == 3) LineInput::interrupt_prompt();
        return 0.01;
    };
    LineInput in(o);
    p.write("half a li");
    CHECK(in.read("> ").kind == Kind::interrupted);
    p.write("ne\nnext\n");
    CHECK(in.read("> ").text == "ne");
    CHECK(in.read("> ").text == "next");
}

TEST_CASE("the history lives under XDG_STATE_HOME, else ~/.local/state", "[frontend]") {
    const char* old_state = std::getenv("XDG_STATE_HOME");
    const std::string saved_state = old_state ? old_state : "";
    const char* old_home = std::getenv("HOME");
    const std::string saved_home = old_home ? old_home : "";
    ::setenv("XDG_STATE_HOME", "/tmp/state", 1);
    CHECK(gaitlab::cli::default_history_file() == "/tmp/state/gaitlab/history");
    ::setenv("XDG_STATE_HOME", "", 1);
    ::setenv("HOME", "/home/someone", 1);
    CHECK(gaitlab::cli::default_history_file() == "/home/someone/.local/state/gaitlab/history");
    ::unsetenv("XDG_STATE_HOME");
    ::unsetenv("HOME");
    CHECK(gaitlab::cli::default_history_file().empty());
    if (old_state) ::setenv("XDG_STATE_HOME", saved_state.c_str(), 1);
    if (old_home) ::setenv("HOME", saved_home.c_str(), 1);
}
