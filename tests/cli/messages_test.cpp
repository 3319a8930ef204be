// gaitlab's messages quote strings from scripts (names, values, paths, Lua errors): on the
// terminal their control characters are written as \xNN, whichever way the message came (a
// gaitlab error, a Lua error, a report while the script runs, the console), and printable
// UTF-8 is left as it is. What the script writes itself stays its own.
#include <catch2/catch.hpp>

#include <string>

#include "run_gaitlab.h"
#include "temp_dir.h"

using gaitlab::test::Output;
using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// whether `text` holds a byte a terminal would act on: C0 but line end and tab, DEL, a C1
// control alone or in UTF-8 (0xc2 0x80-0x9f), or a byte that UTF-8 never has
bool has_control(const std::string& text) {
    for (size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        const auto before = i > 0 ? static_cast<unsigned char>(text[i - 1]) : 0;
        if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7f) return true;
        if (c >= 0x80 && c <= 0x9f && (before < 0x80 || before == 0xc2)) return true;
        if (c == 0xc0 || c == 0xc1 || c >= 0xf5) return true;
    }
    return false;
}

// runs `script` (the text of a .lua file) as `gaitlab run --no-record`
Output run_script(const TempDir& dir, const std::string& script) {
    write_text(dir / "script.lua", script);
    return run_gaitlab({"run", "--no-record", "script.lua"}, dir.str());
}

}  // namespace

TEST_CASE("an error quoting a script's string writes its control characters as hex escapes",
          "[cli][messages]") {
    TempDir dir("cli_messages_error");
    // a gaitlab error (an unknown module type) quoting an escape sequence and a zero byte
    Output r = run_script(dir, "gaitlab.robot.chain{ modules = 2, module = 'y1\\27[31m\\0red' }\n");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains("unknown module type 'y1\\x1b[31m\\x00red'"));
    CHECK_FALSE(has_control(r.err));
    CHECK(r.err.find('\0') == std::string::npos);
    // a robot name: refused by the name check, which shows it the same way
    r = run_script(dir, "gaitlab.robot.chain{ name = 'snake\\27[31m\\0', modules = 2 }\n");
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains("(got \"snake\\x1b[31m\\x00\")"));
    CHECK_FALSE(has_control(r.err));
    // a Lua error the script raises (no gaitlab code in between): a terminal title, a clear
    // screen, C1's CSI in UTF-8 and alone, a byte that is no UTF-8
    r = run_script(dir, "error('boom \\27]0;pwned\\7 \\27[2J \\194\\155 \\155 \\255')\n");
    CHECK(r.status == 1);
    CHECK(r.err ==
          "gaitlab: script.lua:1: boom \\x1b]0;pwned\\x07 \\x1b[2J \\xc2\\x9b \\x9b \\xff\n");
    // an error of Lua's own (require's message names the module)
    r = run_script(dir, "require('\\27[31mmod')\n");
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains("module '\\x1b[31mmod' not found:\n\t"));
    CHECK_FALSE(has_control(r.err));
}

TEST_CASE("printable UTF-8 in a message is left as it is", "[cli][messages]") {
    TempDir dir("cli_messages_utf8");
    Output r = run_script(dir, "gaitlab.robot.chain{ modules = 2, module = '\xce\xbc' }\n");
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::Contains("unknown module type '\xce\xbc'"));
    r = run_script(dir,
                   "error('0.4 N\xc2\xb7m, \xce\xbc = 0.8, caf\xc3\xa9 \xf0\x9f\x90\x8d', 0)\n");
    CHECK(r.err == "gaitlab: 0.4 N\xc2\xb7m, \xce\xbc = 0.8, caf\xc3\xa9 \xf0\x9f\x90\x8d\n");
}

TEST_CASE(
    "a report while the script runs is written as terminal text, the script's own output "
    "is its own",
    "[cli][messages]") {
    TempDir dir("cli_messages_report");
    // a controller failing under on_controller_error = "continue" is reported, and the run goes
    // on; what the script prints and writes to stderr itself is written as it is
    const Output r = run_script(dir,
                                "local C = gaitlab.controller{ name = 'c', step = function() "
                                "error('bad \\27[31mred') end }\n"
                                "local robot = gaitlab.robot.chain{ modules = 2 }\n"
                                "local world = gaitlab.world()\n"
                                "world:add(robot)\n"
                                "robot:group('all'):drive(C{})\n"
                                "gaitlab.simulation{ world = world, on_controller_error = "
                                "'continue' }:run(0.1)\n"
                                "print('\\27[1mbold')\n"
                                "io.stderr:write('\\27[4mmine\\n')\n");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.out == "\x1b[1mbold\n");
    const size_t report = r.err.find("gaitlab: controller 'c' failed: ");
    REQUIRE(report != std::string::npos);
    const std::string line = r.err.substr(report, r.err.find('\n', report) - report);
    CHECK_THAT(line, Catch::EndsWith("bad \\x1b[31mred"));
    CHECK_THAT(r.err, Catch::EndsWith("\x1b[4mmine\n"));
    CHECK_FALSE(has_control(r.err.substr(0, r.err.rfind("\x1b[4mmine"))));
}

TEST_CASE("the console writes its errors as terminal text, its results as they are",
          "[cli][messages][console]") {
    TempDir dir("cli_messages_console");
    // lines typed (piped) at the console: a gaitlab error, a Lua error, a result and a print
    const Output r = run_gaitlab({"console", "--no-record"}, dir.str(),
                                 "gaitlab.robot.chain{ modules = 2, module = 'y1\\27[31m\\0' }\n"
                                 "error('\\27[2J', 0)\n"
                                 "print('\\27[1mbold')\n");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK_THAT(r.err, Catch::Contains("unknown module type 'y1\\x1b[31m\\x00'"));
    CHECK_THAT(r.err, Catch::StartsWith("console:1: bad argument"));
    CHECK_THAT(r.err, Catch::Contains("\n\\x1b[2J\nstack traceback:\n"));
    CHECK_FALSE(has_control(r.err));
    CHECK(r.out == "\x1b[1mbold\n");

    // a script the console opens on (gaitlab -i FILE.lua) that fails
    write_text(dir / "bad.lua", "x = 1\nerror('\\27]0;title\\7')\n");
    const Output i = run_gaitlab({"-i", "--no-record", "bad.lua"}, dir.str(), "print(x)\n");
    INFO(i.err);
    CHECK(i.out == "1\n");
    CHECK_THAT(i.err, Catch::StartsWith("bad.lua:2: \\x1b]0;title\\x07\nstack traceback:"));
    CHECK_FALSE(has_control(i.err));
}
