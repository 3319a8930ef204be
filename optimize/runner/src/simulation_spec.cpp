// A spec's build function made from a simulation file (see simulation_spec.h).
#include "simulation_spec.h"

#include <lua.hpp>

#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/scripting/lua_host.h"

namespace gaitlab::optimize::detail {

namespace {

namespace fs = std::filesystem;

// Called with (path, set, parameters), set: name -> "CONTROLLER.PARAMETER", parameters:
// name -> {min, max}; checks them against the file (errors "FIELD: what", level 0) and returns
// build(p).
const char* const kMaker = R"lua(
local path, set, parameters = ...
local function load()
  local sim, message
  if path:match("%.lua$") then
    local chunk, err = loadfile(path, "t")
    if not chunk then error("simulation: " .. err, 0) end
    sim = chunk()
    if getmetatable(sim) ~= getmetatable(gaitlab.simulation{ world = gaitlab.world{} }) then
      error(string.format("simulation: %s must return a simulation (return gaitlab.simulation{ ... }), got %s",
                          path, type(sim)), 0)
    end
  else
    sim, message = gaitlab.simulation.load(path)
    if not sim then error("simulation: " .. message, 0) end
  end
  return sim
end
-- the controllers of a simulation by name
local function controllers(sim)
  local out, names = {}, {}
  for _, r in ipairs(sim:status().robots) do
    for _, ctl in ipairs(sim:robot(r.name):controllers()) do
      out[ctl.name] = ctl
      names[#names + 1] = "'" .. ctl.name .. "'"
    end
  end
  return out, table.concat(names, ", ")
end
-- parameter name -> { controller name, parameter }
local targets = {}
local sim = load()
local by_name, listed = controllers(sim)
for name, range in pairs(parameters) do
  local target = set[name] or name
  local c, param = target:match("^(.+)%.([^.]+)$")
  local field = set[name] and ("set." .. name) or ("parameters." .. name)
  if not c then
    error(string.format("%s: 'CONTROLLER.PARAMETER' expected (a controller of %s and one of its parameters, e.g. 'sine.amplitude'), got '%s'",
                        field, path, target), 0)
  end
  local ctl = by_name[c]
  if not ctl then
    error(string.format("%s: %s has no controller '%s' (it has %s)", field, path, c,
                        listed ~= "" and listed or "none"), 0)
  end
  local params = ctl:params()
  local info = params[param]
  if not info then
    local known = {}
    for k in pairs(params) do known[#known + 1] = "'" .. k .. "'" end
    table.sort(known)
    error(string.format("%s: controller '%s' has no parameter '%s' (it has %s)", field, c, param,
                        table.concat(known, ", ")), 0)
  end
  if range[1] < info.min or range[2] > info.max then
    error(string.format("parameters.%s: the range [%s, %s] goes outside %s's [%s, %s]", name,
                        range[1], range[2], target, info.min, info.max), 0)
  end
  targets[name] = { c, param }
end
for name in pairs(set) do
  if not parameters[name] then
    error(string.format("set.%s: no parameter '%s' to set (set names parameters)", name, name), 0)
  end
end
return function(p)
  local s = load()
  local ctls = controllers(s)
  for name, t in pairs(targets) do
    ctls[t[1]][t[2]] = p[name]
  end
  return s
end
)lua";

[[noreturn]] void bad(const std::string& file, const std::string& what) {
    throw SpecError(fmt::format("{}: {}", file, what));
}

}  // namespace

void install_simulation_build(scripting::LuaHost& host, const std::string& file) {
    lua_State* L = host.state();
    const int spec = lua_gettop(L);
    lua_getfield(L, spec, "simulation");
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        lua_getfield(L, spec, "set");
        const bool has_set = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (has_set)
            bad(file,
                "set: only with simulation = \"FILE.xml\" (a build function sets "
                "what it likes)");
        return;
    }
    if (lua_type(L, -1) != LUA_TSTRING) {
        bad(file, fmt::format("simulation: a simulation file's name (FILE.xml or FILE.lua) "
                              "expected, got {}",
                              luaL_typename(L, -1)));
    }
    std::string path = lua_tostring(L, -1);
    lua_pop(L, 1);
    lua_getfield(L, spec, "build");
    const bool has_build = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (has_build) bad(file, "build: give build or simulation, not both");
    // relative to the spec file's folder
    const fs::path resolved =
        fs::path(path).is_absolute() ? fs::path(path) : fs::path(file).parent_path() / path;
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec)) {
        bad(file, fmt::format("simulation: {}: no such file (relative to the spec's folder)",
                              resolved.string()));
    }
    path = resolved.string();

    // set: name -> "CONTROLLER.PARAMETER"
    lua_getfield(L, spec, "set");
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        lua_newtable(L);
    } else if (!lua_istable(L, -1)) {
        bad(file, fmt::format("set: a table {{ PARAMETER = \"CONTROLLER.PARAMETER\", ... }} "
                              "expected, got {}",
                              luaL_typename(L, -1)));
    }
    const int set = lua_gettop(L);
    lua_pushnil(L);
    while (lua_next(L, set) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING) {
            bad(file,
                "set: a table { PARAMETER = \"CONTROLLER.PARAMETER\", ... } expected (names "
                "and strings)");
        }
        lua_pop(L, 1);
    }
    lua_getfield(L, spec, "parameters");
    if (!lua_istable(L, -1)) {
        lua_pop(L, 2);
        return;  // read_spec says what is wrong with it
    }
    const int parameters = lua_gettop(L);
    if (luaL_loadbufferx(L, kMaker, std::strlen(kMaker), "=(gaitlab optimize)", "t") != LUA_OK) {
        throw Error(std::string("optimize: ") + lua_tostring(L, -1));
    }
    lua_pushstring(L, path.c_str());
    lua_pushvalue(L, set);
    lua_pushvalue(L, parameters);
    try {
        scripting::protected_call(L, 3, 1);
    } catch (const scripting::ScriptError& e) {
        // the maker's own checks have no position; errors of the file keep theirs
        lua_settop(L, spec);
        std::string message = e.what();
        if (e.file() == "(gaitlab optimize)") {
            const std::string at = fmt::format(":{}: ", e.line());
            const auto pos = message.find(at);
            if (pos != std::string::npos) message = message.substr(pos + at.size());
        }
        bad(file, message);
    }
    lua_setfield(L, spec, "build");
    lua_settop(L, spec);
}

}  // namespace gaitlab::optimize::detail
