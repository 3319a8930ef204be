// The fitness of an optimization spec (see fitness.h).
#include "fitness.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/optimize/runner.h"
#include "gaitlab/suggest.h"

namespace gaitlab::optimize::detail {

namespace {

const std::vector<std::string> kNames = {"distance", "speed", "cost_of_transport", "heading"};

const char* const kExpected =
    "expected \"distance\", \"speed\", \"cost_of_transport\", \"heading\", { direction = {X, Y} "
    "} or a function(sim, p)";

// Errors are raised without a position (level 0): the runner adds the spec file's name.
const char* const kMeasure = R"lua(
local sim, settle, duration, kind, robot_name, fitness, p, dx, dy = ...
local index
if kind ~= "function" then
  local robots = sim:status().robots
  if robot_name ~= "" then
    for i, r in ipairs(robots) do
      if r.name == robot_name then index = i end
    end
    if not index then
      local names = {}
      for _, r in ipairs(robots) do names[#names + 1] = "'" .. r.name .. "'" end
      error(string.format("robot: the simulation has no robot '%s' (it has %s)", robot_name,
                          #names > 0 and table.concat(names, ", ") or "none"), 0)
    end
  elseif #robots ~= 1 then
    error(string.format("fitness '%s' measures one robot, but the simulation has %d: name it " ..
                        "with robot = \"NAME\"", kind, #robots), 0)
  else
    index = 1
  end
end
if settle > 0 then sim:run(settle) end
local status = index and sim:status()
local start = index and status.robots[index]
-- the servos' energy (robot:energy(), integrated by the simulation every physics step)
local joules = kind == "cost_of_transport" and start.energy
sim:run(duration)
if kind == "function" then return fitness(sim, p) end
local e = sim:status().robots[index]
local ddx, ddy = e.position.x - start.position.x, e.position.y - start.position.y
local d = math.sqrt(ddx ^ 2 + ddy ^ 2)
if kind == "distance" then return d end
if kind == "speed" then return d / duration end
if kind == "direction" then return ddx * dx + ddy * dy end
if kind == "heading" then return (e.turned - start.turned) / duration end
-- cost of transport: energy / (weight * distance), negated (lower costs rank higher)
joules = e.energy - joules
local mass = 0
for _, b in ipairs(sim:robot(e.name):bodies()) do mass = mass + b.mass end
if not (d >= 1e-3) then
  error(string.format("cost_of_transport: the robot moved %.3g m: no cost of transport", d), 0)
end
return -joules / (mass * 9.81 * d)
)lua";

}  // namespace

void read_fitness(lua_State* L, Spec& spec) {
    const std::string& file = spec.file;
    const auto bad = [&](const std::string& what) {
        throw SpecError(fmt::format("{}: fitness: {}", file, what));
    };
    if (lua_isfunction(L, -1)) {
        spec.fitness = "function";
    } else if (lua_type(L, -1) == LUA_TSTRING) {
        spec.fitness = lua_tostring(L, -1);
        if (std::find(kNames.begin(), kNames.end(), spec.fitness) == kNames.end()) {
            bad(fmt::format("unknown fitness '{}'{} ({})", spec.fitness,
                            did_you_mean(spec.fitness, kNames), kExpected));
        }
    } else if (lua_istable(L, -1)) {
        // { direction = {X, Y} }: the displacement along that direction
        lua_pushnil(L);
        while (lua_next(L, -2) != 0) {
            const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "";
            lua_pop(L, 1);
            if (key != "direction") {
                lua_pop(L, 1);
                bad(fmt::format("unknown key '{}' in the table{} ({})",
                                key.empty() ? "(not a name)" : key,
                                did_you_mean(key, {"direction"}), kExpected));
            }
        }
        lua_getfield(L, -1, "direction");
        if (!lua_istable(L, -1)) {
            bad(fmt::format("direction: a direction {{X, Y}} of two numbers expected, got {}",
                            luaL_typename(L, -1)));
        }
        double d[2] = {0, 0};
        for (int i = 0; i < 2; ++i) {
            lua_rawgeti(L, -1, i + 1);
            const bool ok = lua_type(L, -1) == LUA_TNUMBER;
            const std::string type = luaL_typename(L, -1);
            d[i] = lua_tonumber(L, -1);
            lua_pop(L, 1);
            if (!ok) {
                bad(
                    fmt::format("direction: a direction {{X, Y}} of two numbers expected, its {} "
                                "is a {}",
                                i == 0 ? "X" : "Y", type));
            }
            if (!std::isfinite(d[i])) {
                bad(fmt::format("direction: {} must be a finite number (got {})",
                                i == 0 ? "X" : "Y",
                                std::isnan(d[i]) ? "nan"
                                : d[i] > 0       ? "inf"
                                                 : "-inf"));
            }
        }
        const bool longer = lua_rawlen(L, -1) != 2;
        lua_pop(L, 1);
        if (longer) bad("direction: a direction {X, Y} of two numbers expected");
        const double length = std::hypot(d[0], d[1]);
        if (!(length > 0)) bad("direction: {0, 0} has no direction (expected {X, Y} not both 0)");
        spec.fitness = "direction";
        spec.direction = {d[0] / length, d[1] / length};
    } else {
        bad(fmt::format("{} ({})",
                        lua_isnil(L, -1) ? "missing" : "got " + std::string(luaL_typename(L, -1)),
                        kExpected));
    }
}

void read_cases(lua_State* L, Spec& spec) {
    const std::string& file = spec.file;
    // a sequence {v1, v2, ...}, no other keys; returns its length
    const auto sequence = [&](const char* field, const char* expected) -> lua_Integer {
        if (!lua_istable(L, -1)) {
            throw SpecError(fmt::format("{}: {}: {} expected, got {}", file, field, expected,
                                        luaL_typename(L, -1)));
        }
        const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
        lua_Integer keys = 0;
        lua_pushnil(L);
        while (lua_next(L, -2) != 0) {
            ++keys;
            lua_pop(L, 1);
        }
        if (n == 0 || keys != n) {
            throw SpecError(fmt::format("{}: {}: {} expected{}", file, field, expected,
                                        n == 0 && keys == 0
                                            ? ", got an empty table"
                                            : " (a list: no other keys, no holes)"));
        }
        return n;
    };
    lua_getfield(L, -1, "worlds");
    if (!lua_isnil(L, -1)) {
        const lua_Integer n = sequence("worlds", "a list of one or more worlds { W1, W2, ... }");
        if (n > 1000) {
            throw SpecError(fmt::format("{}: worlds: at most 1000 expected, got {}", file, n));
        }
        spec.worlds = static_cast<int>(n);
    }
    lua_pop(L, 1);
    lua_getfield(L, -1, "seeds");
    if (!lua_isnil(L, -1)) {
        const char* expected = "a list of one or more seeds { 1, 2, 3 } (whole numbers >= 0)";
        const lua_Integer n = sequence("seeds", expected);
        if (n > 1000) {
            throw SpecError(fmt::format("{}: seeds: at most 1000 expected, got {}", file, n));
        }
        for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, -1, i);
            if (!lua_isinteger(L, -1) || lua_tointeger(L, -1) < 0) {
                const std::string got = lua_type(L, -1) == LUA_TNUMBER
                                            ? fmt::format("{}", lua_tonumber(L, -1))
                                            : luaL_typename(L, -1);
                throw SpecError(fmt::format("{}: seeds[{}]: a whole number >= 0 expected, got {}",
                                            file, i, got));
            }
            const auto seed = static_cast<std::uint64_t>(lua_tointeger(L, -1));
            lua_pop(L, 1);
            if (std::find(spec.seeds.begin(), spec.seeds.end(), seed) != spec.seeds.end()) {
                throw SpecError(fmt::format("{}: seeds[{}]: {} is given twice (each seed once)",
                                            file, i, seed));
            }
            spec.seeds.push_back(seed);
        }
    }
    lua_pop(L, 1);
}

const char* measure_chunk() {
    return kMeasure;
}

}  // namespace gaitlab::optimize::detail
