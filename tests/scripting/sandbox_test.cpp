// What a sandboxed controller file can and cannot do (scripting/src/sandbox.cpp): no escape to
// an unsandboxed load, no reach into the script's string metatable or gaitlab's metatables, no
// writes outside its folder, no finalizers, no pattern that matches for hours.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "lua_fixture.h"
#include "sandbox.h"
#include "temp_dir.h"

using gaitlab::scripting::pattern_cost;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace fs = std::filesystem;

TEST_CASE("a sandboxed file cannot load an unsandboxed one", "[sandbox]") {
    TempDir tmp("sandbox_load");
    LuaFixture lua;
    write_text(tmp / "evil.lua",
               "os.execute('touch " + (tmp / "ran") +
                   "')\nreturn gaitlab.controller{ name = 'evil', step = function() end }");
    write_text(tmp / "loader.lua", R"(
local Evil = gaitlab.controller.load("evil.lua", { sandbox = false })
return Evil)");
    CHECK_THAT(lua.error_of("gaitlab.controller.load('" + (tmp / "loader.lua") + "')"),
               Catch::Contains("field 'sandbox': a sandboxed controller file can only load "
                               "files in a sandbox"));
    // loading it sandboxed is fine: os is simply not there
    write_text(tmp / "loader.lua", "return gaitlab.controller.load('evil.lua')");
    CHECK_THAT(lua.error_of("gaitlab.controller.load('" + (tmp / "loader.lua") + "')"),
               Catch::Contains("evil.lua:1: attempt to index a nil value (global 'os')"));
    CHECK_FALSE(fs::exists(tmp / "ran"));
    // and a sandbox cannot reload the script's files either
    write_text(tmp / "reloader.lua",
               "assert(gaitlab.controller.reload == nil)\nreturn gaitlab.controller.load("
               "'evil2.lua')");
    write_text(tmp / "evil2.lua", "return gaitlab.controller{ name = 'e2', step = print }");
    lua.run("gaitlab.controller.load('" + (tmp / "reloader.lua") + "')");
}

TEST_CASE("a sandboxed file loads controller files from its own folder only", "[sandbox]") {
    // it could load any path: the error then told whether a file existed and showed its first
    // words ("secret.txt:1: syntax error near 'stuff'")
    TempDir tmp("sandbox_load_outside");
    namespace fs = std::filesystem;
    fs::create_directories(tmp.path / "ctl/sub");
    write_text(tmp / "secret.txt", "very secret stuff\n");
    write_text(tmp / "ctl/sub/helper.lua",
               "return gaitlab.controller{ name = 'helper', step = function() end }");
    fs::create_symlink(tmp / "secret.txt", tmp / "ctl/link.lua");
    LuaFixture lua;
    for (const std::string& target :
         {std::string("../secret.txt"), tmp / "secret.txt", std::string("link.lua"),
          std::string("../nothing.lua"), std::string("/etc/passwd")}) {
        INFO(target);
        write_text(tmp / "ctl/spy.lua", "return gaitlab.controller.load('" + target + "')");
        const std::string message =
            lua.error_of("gaitlab.controller.load('" + (tmp / "ctl/spy.lua") + "')");
        CHECK_THAT(message, Catch::Contains("cannot load controller '" + target +
                                            "': outside the folder of the sandboxed controller "
                                            "file"));
        CHECK_THAT(message, !Catch::Contains("secret stuff") && !Catch::Contains("no file"));
    }
    // inside its folder, subfolders too, it loads as before
    write_text(tmp / "ctl/user.lua", "return gaitlab.controller.load('sub/helper.lua')");
    CHECK(lua.string("gaitlab.controller.load('" + (tmp / "ctl/user.lua") + "').name") == "helper");
}

TEST_CASE("a sandboxed file cannot change what the script uses", "[sandbox]") {
    TempDir tmp("sandbox_meta");
    LuaFixture lua;
    lua.run("robot = gaitlab.robot.chain{ modules = 2 }");
    // the strings' metatable, gaitlab's metatables, the libraries and gaitlab.controller
    write_text(tmp / "meddle.lua", R"(
assert(getmetatable("") == nil, "string metatable visible")
assert(getmetatable(gaitlab.controller) == nil, "controller table's metatable visible")
string.upper = function() return "hacked" end
math.pi = 3
gaitlab.controller.load = nil
local own = setmetatable({}, { __index = { x = 1 } })
assert(getmetatable(own).__index.x == 1, "own metatable hidden")
assert(not pcall(setmetatable, {}, { __gc = print }), "__gc allowed")
return gaitlab.controller{ name = "meddle", step = function() end })");
    lua.run("Meddle = gaitlab.controller.load('" + (tmp / "meddle.lua") + "')");
    CHECK(lua.string("string.upper('a')") == "A");
    CHECK(lua.string("('a'):upper()") == "A");
    CHECK(lua.number("math.pi") == Approx(3.14159265));
    CHECK(lua.boolean("type(gaitlab.controller.load) == 'function'"));
    // gaitlab's objects show their type name, never their metatable, to anyone
    CHECK(lua.string("getmetatable(robot)") == "gaitlab.Robot");
    CHECK(lua.string("getmetatable(Meddle)") == "gaitlab.ControllerClass");
    CHECK_THAT(lua.error_of("getmetatable(robot).__gc(42)"),
               Catch::Contains("attempt to call a nil value (field '__gc')"));
    CHECK(lua.integer("#robot:joints()") == 2);
}

TEST_CASE("a sandboxed file writes templates only inside its own folder", "[sandbox]") {
    TempDir tmp("sandbox_write");
    fs::create_directories(tmp.path / "ctl");
    LuaFixture lua;
    write_text(tmp / "ctl/writer.lua", R"(
local outside = {}
for _, p in ipairs({ "../escaped.lua", "/tmp/../" .. "escaped_abs.lua", "sub/../../up.lua", "." }) do
  local ok, err = gaitlab.controller.write_template("sine", p)
  assert(ok == nil and err:find("outside the folder of the sandboxed controller file"), p)
end
assert(gaitlab.controller.write_template("sine", "mine.lua"))
return gaitlab.controller{ name = "writer", step = function() end })");
    lua.run("gaitlab.controller.load('" + (tmp / "ctl/writer.lua") + "')");
    CHECK(fs::exists(tmp.path / "ctl/mine.lua"));
    CHECK_FALSE(fs::exists(tmp.path / "escaped.lua"));
    CHECK_FALSE(fs::exists(tmp.path / "up.lua"));
    // a link inside the folder that points out of it does not help
    fs::create_directory_symlink(tmp.path, tmp.path / "ctl/out");
    write_text(tmp / "ctl/linker.lua", R"(
local ok, err = gaitlab.controller.write_template("sine", "out/linked.lua")
assert(ok == nil, "wrote through a link")
return gaitlab.controller{ name = "linker", step = function() end })");
    lua.run("gaitlab.controller.load('" + (tmp / "ctl/linker.lua") + "')");
    CHECK_FALSE(fs::exists(tmp.path / "linked.lua"));
    // a script may write wherever it likes
    lua.run("assert(gaitlab.controller.write_template('sine', '" + (tmp / "script.lua") + "'))");
    CHECK(fs::exists(tmp.path / "script.lua"));
}

TEST_CASE("a sandboxed file may create folders inside its folder, never outside", "[sandbox]") {
    TempDir tmp("sandbox_folders");
    fs::create_directories(tmp.path / "ctl");
    fs::create_directory_symlink(tmp.path, tmp.path / "ctl/out");
    LuaFixture lua;
    write_text(tmp / "ctl/maker.lua", R"(
local refused = 0
for _, p in ipairs({ "new/../../escaped.lua", "a/b/../../../escaped.lua", "out/new/linked.lua",
                     "out/escaped.lua", "/tmp/gaitlab_sandbox_new/x.lua",
                     "new/../new/../.." }) do
  local ok, err = gaitlab.controller.write_template("sine", p)
  local want = p .. ": outside the folder of the sandboxed controller file ("
  assert(ok == nil and err:sub(1, #want) == want, tostring(err))
  refused = refused + 1
end
assert(refused == 6)
local written = assert(gaitlab.controller.write_template("sine", "gaits/new/mine.lua"))
assert(written:sub(-#"/ctl/gaits/new/mine.lua") == "/ctl/gaits/new/mine.lua", written)
assert(gaitlab.controller.write_template("sine", "gaits/x/../y/other.lua"))
return gaitlab.controller{ name = "maker", step = function() end })");
    lua.run("gaitlab.controller.load('" + (tmp / "ctl/maker.lua") + "')");
    CHECK(fs::is_regular_file(tmp.path / "ctl/gaits/new/mine.lua"));
    CHECK(fs::is_regular_file(tmp.path / "ctl/gaits/y/other.lua"));
    // nothing was made outside: no file, no folder
    CHECK_FALSE(fs::exists(tmp.path / "ctl/gaits/x"));  // paths are normalized before use
    for (const char* made : {"escaped.lua", "new", "a", "linked.lua"})
        CHECK_FALSE(fs::exists(tmp.path / made));
    CHECK_FALSE(fs::exists("/tmp/gaitlab_sandbox_new"));
    CHECK_FALSE(fs::exists(tmp.path / "ctl/new"));
    CHECK_FALSE(fs::exists(tmp.path / "ctl/a"));
}

TEST_CASE("sandboxed code cannot match a pattern for hours", "[sandbox]") {
    CHECK(pattern_cost("abc", 100) == Approx(101));
    CHECK(pattern_cost("^abc", 100) == Approx(1));
    CHECK(pattern_cost("a*b", 100) == Approx(101 * 101));
    CHECK(pattern_cost("^%s*(.-)%s*$", 10) == Approx(11 * 11 * 11));
    CHECK(pattern_cost("[%]*]+x?", 10) == Approx(11 * 11 * 2));
    CHECK(pattern_cost("%bxy%f[%w]", 10) == Approx(11 * 11));
    TempDir tmp("sandbox_pattern");
    LuaFixture lua;
    write_text(tmp / "bomb.lua", R"(
local s = string.rep("a", 3000)
local ok, err = pcall(string.find, s, "a*a*a*a*b")
assert(not ok and err:find("pattern too costly for a sandboxed controller"), err)
ok, err = pcall(function() return s:match(".-.-.-.-b") end)
assert(not ok and err:find("pattern too costly"), err)
ok, err = pcall(function() for _ in s:gmatch("^a*a*a*b") do end end)
assert(not ok and err:find("pattern too costly"), err)
-- everyday patterns on everyday strings work, and so does a plain search
assert(("left = 12"):match("^(%w+)%s*=%s*(%d+)$") == "left")
assert(s:find("a*b", 1, true) == nil)
assert(select(2, ("a,b,c"):gsub(",", ";")) == 2)
return gaitlab.controller{ name = "bomb", step = function() end })");
    lua.run("gaitlab.controller.load('" + (tmp / "bomb.lua") + "')");
    // the script's own patterns are its business
    CHECK(lua.boolean("string.find(string.rep('a', 50), 'a*a*b') == nil"));
}
