// Messages as the terminal gets them (gaitlab/terminal.h) and the zero byte of an Error's
// message (gaitlab/error.h): one convention, \xNN.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

#include "gaitlab/error.h"
#include "gaitlab/terminal.h"
#include "temp_dir.h"

using gaitlab::terminal_line;
using gaitlab::terminal_text;
using namespace std::string_literals;

TEST_CASE("control characters are written as hex escapes, printable UTF-8 as it is", "[terminal]") {
    // C0 (an escape sequence, a bell, a carriage return), NUL, DEL
    CHECK(terminal_text("red \x1b[31mtext\x1b[0m") == "red \\x1b[31mtext\\x1b[0m");
    CHECK(terminal_text("title \x1b]0;pwned\x07") == "title \\x1b]0;pwned\\x07");
    CHECK(terminal_text("a\0b"s) == "a\\x00b");
    CHECK(terminal_text("over\rwrite") == "over\\x0dwrite");
    CHECK(terminal_text("del\x7f") == "del\\x7f");
    // line ends and tabs stay: messages span lines (a traceback, a list of places searched)
    CHECK(terminal_text("one\n\ttwo\n") == "one\n\ttwo\n");
    // C1 controls in their UTF-8 form (U+009B is CSI), and as lone bytes (invalid UTF-8)
    CHECK(terminal_text("csi \xc2\x9b"
                        "2J") == "csi \\xc2\\x9b2J");
    CHECK(terminal_text("nel \xc2\x85") == "nel \\xc2\\x85");
    CHECK(terminal_text("lone \x9b"
                        "2J") == "lone \\x9b2J");
    // bytes that are not valid UTF-8: lone, cut, overlong, surrogates, past U+10FFFF
    CHECK(terminal_text("bad\xff\xfe") == "bad\\xff\\xfe");
    CHECK(terminal_text("cut\xe8\x9b") == "cut\\xe8\\x9b");
    CHECK(terminal_text("cut \xe8\x9b"
                        "x") == "cut \\xe8\\x9bx");
    CHECK(terminal_text("over\xc0\xaf") == "over\\xc0\\xaf");
    CHECK(terminal_text("sur\xed\xa0\x80") == "sur\\xed\\xa0\\x80");
    CHECK(terminal_text("big\xf4\x90\x80\x80") == "big\\xf4\\x90\\x80\\x80");
    // a valid sequence after a bad byte is kept
    CHECK(terminal_text("\xff\xce\xbc") == "\\xff\xce\xbc");
    // printable UTF-8 as it is: N·m, μ, é, U+00A0 (the first code point past C1), an emoji
    for (const std::string s : {"N\xc2\xb7m", "\xce\xbc", "caf\xc3\xa9", "\xc2\xa0",
                                "\xf0\x9f\x90\x8d", "plain ASCII ~!@#$%^&*()\\"}) {
        CHECK(terminal_text(s) == s);
    }
    // what it writes is terminal text already
    const std::string once = terminal_text("\x1b\0\xc2\x9b\xff"s);
    CHECK(once == "\\x1b\\x00\\xc2\\x9b\\xff");
    CHECK(terminal_text(once) == once);
}

TEST_CASE("a line keeps to one line: line ends and tabs are escaped too", "[terminal]") {
    CHECK(terminal_line("a\nb\tc\x1b") == "a\\x0ab\\x09c\\x1b");
    CHECK(terminal_line("N\xc2\xb7m") == "N\xc2\xb7m");
}

TEST_CASE("print_message formats as printf and writes terminal text", "[terminal]") {
    gaitlab::test::TempDir tmp("terminal_print");
    std::FILE* f = std::fopen(tmp.file("out").c_str(), "wb");
    REQUIRE(f != nullptr);
    gaitlab::print_message(f, "gaitlab: %s (%d)\n", "robot '\x1b[2J'", 3);
    gaitlab::write_message(f, "zero \0 \xce\xbc\n"s);
    std::fclose(f);
    CHECK(gaitlab::test::read_text(tmp.file("out")) ==
          "gaitlab: robot '\\x1b[2J' (3)\nzero \\x00 \xce\xbc\n");
}

TEST_CASE("an Error's message writes a zero byte as the terminal does", "[terminal]") {
    const gaitlab::Error e("unknown module type 'y1\0x'"s);
    CHECK(std::string(e.what()) == "unknown module type 'y1\\x00x'");
    CHECK(terminal_text(e.what()) == e.what());
    // the other bytes are the message's: the terminal writes them
    const gaitlab::SpecError s("name '\x1b[31m'");
    CHECK(std::string(s.what()) == "name '\x1b[31m'");
}
