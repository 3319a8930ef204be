// The host's pairs and table.sort (scripting/src/fixed_order.cpp): the same order in every
// process and state, gaitlab's handles as keys included, also in the sandboxes of an interpreter
// that required gaitlab.
#include <catch2/catch.hpp>

#include <string>

#include "cli/run_gaitlab.h"
#include "fixed_order.h"
#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::test::InterpreterState;
using gaitlab::test::LuaFixture;
using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// Handles of every kind, made in an order that has nothing to do with their addresses: `junk`
// tables allocated first and between them move each to another place (the chunk's argument,
// `...`, or the script's, arg[1], says how many). `made` names them in the order they were made;
// `order` names them in the order pairs visits a table keyed by them, filled in yet another order.
const std::string kHandles = R"(
local junk_count = tonumber((...) or (arg and arg[1]) or 0)
local junk = {}
local function perturb(n)
  for i = 1, n do junk[#junk + 1] = { i, tostring(i) } end
end
perturb(junk_count)
made, label = {}, {}
local handles = {}
local function note(name, h)
  assert(label[h] == nil, name .. " is not a new handle")
  label[h] = name
  made[#made + 1] = name
  handles[#handles + 1] = h
  perturb(#made * 37 % 11 + junk_count % 5)
  return h
end
note("y1", gaitlab.modules.y1)
local robots = {}
for i = 1, 4 do
  robots[i] = note("robot" .. i, gaitlab.robot.chain{ name = "r" .. i, modules = 3 })
end
local world = note("world", gaitlab.world())
for i = 4, 1, -1 do world:add(robots[i], { y = i }) end
note("sensor4", robots[4]:sensor{ kind = "joint", joint = 1 })
note("group2", robots[2]:group{ 1, 2 })
local sine = note("sine", gaitlab.controllers.sine{})
local class = note("class", gaitlab.controller{ name = "c", step = function() end })
note("sensor1", robots[1]:sensor{ kind = "imu", module = 2 })
local group3 = note("group3", robots[3]:group("all"))
local own = note("own", class{})
note("group1", robots[1]:group{ 3 })
group3:drive(own)
robots[2]:group{ 1, 2 }:drive(sine)
local sim = note("simulation", gaitlab.simulation{ world = world })
note("actuation", robots[1]:actuation())
note("sensor2", robots[2]:sensor{ kind = "contact", module = 1 })
note("live", sim:live{ series = { "r1.com.x" } })
local keyed = {}
for i = 1, #handles do
  local h = handles[(i * 7) % #handles + 1]
  keyed[h] = label[h]
end
local seen = {}
for h, name in pairs(keyed) do
  assert(label[h] == name)
  seen[#seen + 1] = name
end
order = table.concat(seen, " ")
made = table.concat(made, " ")
)";

}  // namespace

TEST_CASE("pairs visits a table's keys in one order, whatever the process or state",
          "[fixed_order]") {
    // Lua's own next visits string keys in an order seeded from addresses and the clock: two
    // states, even in one process, disagree. The host's pairs orders them by value.
    const std::string order = R"(
        local t = {}
        for i = 1, 200 do t["key" .. i] = i end
        local seen = {}
        for k in pairs(t) do seen[#seen + 1] = k end
        return table.concat(seen, ",", 1, 5))";
    LuaFixture one, two;
    one.run("first = (function() " + order + " end)()");
    two.run("first = (function() " + order + " end)()");
    CHECK(one.string("first") == "key1,key10,key100,key101,key102");
    CHECK(two.string("first") == one.string("first"));

    LuaFixture lua;
    lua.run(R"(
        local long = string.rep("x", 60)  -- a long string, which Lua does not intern
        local t = { 30, 10, b = 1, a = 1, [long .. "b"] = 1, [long .. "a"] = 1, [true] = 1,
                    [false] = 1, [2.5] = 1, [-7] = 1, ab = 1, [""] = 1 }
        local seen = {}
        for k in pairs(t) do
            seen[#seen + 1] = type(k) == "string" and #k > 50 and k:sub(-1) .. "#" .. #k
                              or tostring(k)
        end
        order = table.concat(seen, " ")
        -- fields cleared during the loop are passed over, values changed are seen changed
        local u = { a = 1, b = 2, c = 3, d = 4 }
        local visited = {}
        for k, v in pairs(u) do
            visited[#visited + 1] = k .. v
            u.c = nil
            if k == "a" then u.d = 40 end
        end
        cleared = table.concat(visited, " ")
        -- a __pairs metamethod still decides
        local p = setmetatable({}, { __pairs = function(self)
            return function(_, k) if not k then return "only", 1 end end, self, nil end })
        for k, v in pairs(p) do meta = k .. v end
        empty = 0
        for _ in pairs({}) do empty = empty + 1 end
    )");
    CHECK(lua.string("order") == "-7 1 2 2.5  a ab b a#61 b#61 false true");
    CHECK(lua.string("cleared") == "a1 b2 d40");
    CHECK(lua.string("meta") == "only1");
    CHECK(lua.integer("empty") == 0);
    CHECK_THAT(lua.error_of("for k in pairs(42) do end"),
               Catch::Contains("bad argument #1 to 'pairs' (table expected, got number)"));
}

TEST_CASE("pairs visits gaitlab's handles in the order they were made", "[fixed_order]") {
    // robots, worlds, sensors, groups, controllers, controller classes, module types,
    // simulations and the values of actuation() and live{}: Lua's own order for them is by
    // address, which changes from one run to the next
    LuaFixture lua;
    lua.run("(function(...) " + kHandles + " end)()");
    CHECK(lua.string("made") ==
          "y1 robot1 robot2 robot3 robot4 world sensor4 group2 sine class sensor1 group3 own "
          "group1 simulation actuation sensor2 live");
    CHECK(lua.string("order") == lua.string("made"));

    // the same in another state whose handles sit elsewhere, junk allocated before and between
    LuaFixture other;
    other.run("(function(...) " + kHandles + " end)(5003)");
    CHECK(other.string("order") == lua.string("order"));

    // a handle collected and made again is a new one, made last (while it is a key, it lives)
    lua.run(R"(
        local function visit(t)
          local seen = {}
          for _, name in pairs(t) do seen[#seen + 1] = name end
          return table.concat(seen, " ")
        end
        local world, y = gaitlab.world(), nil
        kept = (function()  -- x's first handle lives in this call only
          local x = gaitlab.robot.chain{ name = "x", modules = 2 }
          world:add(x)
          y = gaitlab.robot.chain{ name = "y", modules = 2 }
          world:add(y, { y = 1 })
          return visit({ [x] = "x", [y] = "y" })
        end)()
        local sim = gaitlab.simulation{ world = world }
        collectgarbage()
        collectgarbage()
        remade = visit({ [sim:robot("x")] = "x", [y] = "y" })
    )");
    CHECK(lua.string("kept") == "x y");
    CHECK(lua.string("remade") == "y x");
}

TEST_CASE("pairs visits gaitlab's handles in one order in every process", "[fixed_order]") {
    // separate processes place their objects at other addresses (and the junk the argument
    // asks for moves them further)
    TempDir tmp("fixed_order_process");
    write_text(tmp / "handles.lua", kHandles + "\nprint(order)\nprint(made)\n");
    const auto first = run_gaitlab({"run", "--no-record", tmp / "handles.lua"}, tmp.str());
    const auto second = run_gaitlab({"run", "--no-record", tmp / "handles.lua"}, tmp.str());
    const auto moved = run_gaitlab({"run", "--no-record", tmp / "handles.lua", "7919"}, tmp.str());
    INFO(first.err);
    REQUIRE(first.status == 0);
    const auto lines = gaitlab::test::lines(first.out);
    REQUIRE(lines.size() == 2);
    CHECK(lines[0] == lines[1]);
    CHECK(second.out == first.out);
    CHECK(moved.out == first.out);
}

TEST_CASE("pairs visits integers and floats in ascending order, also beyond 2^53",
          "[fixed_order]") {
    LuaFixture lua;
    // an integer near the ends of its range and a float beyond it (2^63, -2^63 - 4096; Lua keeps
    // a float key with an integer value as that integer only when it fits) compared as floats
    // tie: 2^63 came out between math.maxinteger - 1 and math.maxinteger
    lua.run(R"(
        local keys = { math.maxinteger - 1, 2^63, math.maxinteger, 1e19, math.mininteger,
                       math.mininteger + 1, -2^63 - 4096, -1e19, 0.5, -0.5 }
        wrong = {}
        -- other keys and other orders of insertion give Lua's traversal other orders
        for filler = 0, 20 do for shift = 0, #keys - 1 do
          local t = {}
          for i = 1, filler do t[i * 1000003] = true end
          for i = 1, #keys do t[keys[(i + shift) % #keys + 1]] = true end
          local previous
          for k in pairs(t) do
            if previous ~= nil and not (previous < k) then
              wrong[#wrong + 1] = string.format("%s before %s", previous, k)
            end
            previous = k
          end
        end end
        wrong = table.concat(wrong, "; ", 1, math.min(#wrong, 3))
    )");
    CHECK(lua.string("wrong") == "");
}

TEST_CASE("pairs visits numbers, strings, booleans, handles, then other keys", "[fixed_order]") {
    LuaFixture lua;
    lua.run(R"(
        local b = gaitlab.robot.chain{ name = "b", modules = 2 }
        local sensor = b:sensor{ kind = "joint", joint = 2 }
        local a = gaitlab.robot.chain{ name = "a", modules = 2 }
        local t = { [a] = "robot a", [{}] = "table", [print] = "function", "one", "two",
                    [io.stdout] = "file", [sensor] = "sensor", z = "z", [true] = "true",
                    [0.5] = "half", [false] = "false", [b] = "robot b", [""] = "empty",
                    [a:group("all")] = "group" }
        local seen = {}
        for _, v in pairs(t) do seen[#seen + 1] = v end
        known = table.concat(seen, ",", 1, 11)
        local rest = { table.unpack(seen, 12) }
        table.sort(rest)
        others = table.concat(rest, ",")
    )");
    CHECK(lua.string("known") == "half,one,two,empty,z,false,true,robot b,sensor,robot a,group");
    // tables, functions and other userdata (a file) come last, in Lua's order
    CHECK(lua.string("others") == "file,function,table");
}

TEST_CASE("a sandbox's pairs visits handles in the order they were made, also in an interpreter",
          "[fixed_order]") {
    // an interpreter that did require "gaitlab" keeps its own pairs; its sandboxes get the
    // host's, which orders the handles they make (controller classes and controllers)
    TempDir tmp("fixed_order_sandbox");
    write_text(tmp / "ordered.lua", R"(
local made, label, keyed = {}, {}, {}
local junk = {}
for i = 1, 6 do
  for j = 1, i * 5 % 7 do junk[#junk + 1] = {} end
  local class = gaitlab.controller{ name = "c" .. i, step = function() end }
  label[class] = "class" .. i
  made[#made + 1] = "class" .. i
  local instance = class{}
  label[instance] = "instance" .. i
  made[#made + 1] = "instance" .. i
end
for h, name in pairs(label) do keyed[h] = name end
local seen = {}
for _, name in pairs(keyed) do seen[#seen + 1] = name end
local in_order = table.concat(seen, " ") == table.concat(made, " ")
return gaitlab.controller{ name = in_order and "in_order" or "out_of_order",
                           step = function() end }
)");
    InterpreterState lua;
    lua_getglobal(lua.L, "pairs");
    CHECK(lua_tocfunction(lua.L, -1) != gaitlab::scripting::fixed_order_pairs);
    lua_pop(lua.L, 1);
    lua.run("name = gaitlab.controller.load('" + (tmp / "ordered.lua") + "').name");
    lua_getglobal(lua.L, "name");
    CHECK(std::string(luaL_optstring(lua.L, -1, "")) == "in_order");
    lua_pop(lua.L, 1);

    LuaFixture host;
    CHECK(host.string("gaitlab.controller.load('" + (tmp / "ordered.lua") + "').name") ==
          "in_order");
}

TEST_CASE(
    "table.sort keeps equal elements in their order, so a sort's result is the same in "
    "every run",
    "[fixed_order]") {
    // Lua's own sort picks pivots from the clock on long arrays: equal elements came out in a
    // different order from run to run. The host's is a stable merge sort.
    LuaFixture lua;
    lua.run(R"(
        local list = {}
        for i = 1, 1000 do list[i] = { fitness = (i * 7919) % 13, id = i } end
        table.sort(list, function(a, b) return a.fitness > b.fitness end)
        stable = true
        for i = 2, #list do
            local a, b = list[i - 1], list[i]
            if a.fitness < b.fitness or (a.fitness == b.fitness and a.id > b.id) then
                stable = false
            end
        end
        first = list[1].id .. " " .. list[2].id
        local words = { "pear", "apple", "fig", "banana", "apple" }
        table.sort(words)
        words_sorted = table.concat(words, " ")
        local numbers = {}
        for i = 1, 777 do numbers[i] = (i * 104729) % 1009 end
        table.sort(numbers)
        ascending = true
        for i = 2, #numbers do if numbers[i - 1] > numbers[i] then ascending = false end end
        -- an order function that is no order still ends, with every element still there
        local any = { 5, 3, 9, 1, 7 }
        table.sort(any, function() return true end)
        local sum = 0
        for _, v in ipairs(any) do sum = sum + v end
        kept = sum
    )");
    CHECK(lua.boolean("stable"));
    CHECK(lua.string("first") == "6 19");  // the first two of fitness 12, in their order
    CHECK(lua.string("words_sorted") == "apple apple banana fig pear");
    CHECK(lua.boolean("ascending"));
    CHECK(lua.integer("kept") == 25);
    CHECK_THAT(lua.error_of("table.sort({ 3, 1, 2 }, function(a, b) error('no order') end)"),
               Catch::Contains("no order"));
    CHECK_THAT(lua.error_of("table.sort({ 3, {}, 2 })"), Catch::Contains("attempt to compare"));
    CHECK_THAT(lua.error_of("table.sort(nil)"),
               Catch::Contains("bad argument #1 to 'sort' (table expected, got nil)"));
}
