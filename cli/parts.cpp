#include "parts.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <lua.hpp>

#include "gaitlab/files.h"
#include "gaitlab/options.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/suggest.h"
#include "gaitlab/xml.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

// the chunk name of the code PartMaker runs (stripped from the messages of its errors)
constexpr const char* kChunk = "gaitlab make";

// The Lua half of PartMaker: each function takes plain tables and calls the public Lua API,
// so the engine checks every value and words every error.
constexpr const char* kHelpers = R"lua(
local P = {}
_G.gaitlab_parts = P

local function written(path, message)
  if not path then error(message, 0) end
  return path
end

local function sorted_params(params)
  local list = {}
  for name, p in pairs(params) do
    if type(p) == "table" then
      list[#list + 1] = { name = name, value = p.default or p[1], min = p.min, max = p.max,
                          unit = p.unit or "" }
    end
  end
  table.sort(list, function(a, b) return a.name < b.name end)
  return list
end

-- a chain and its sensors: imu and range on the head module, contact on every module, joint
-- on every joint, unless `at` says which
function P.chain(r)
  local robot = gaitlab.robot.chain{ name = r.name, modules = r.modules,
                                     connection = r.connection, module = r.module }
  for _, s in ipairs(r.sensors) do
    local kind, at = s.kind, s.at
    if kind == "imu" or kind == "range" then
      robot:sensor{ kind = kind, module = at or r.modules }
    elseif kind == "contact" then
      if at then
        robot:sensor{ kind = kind, module = at }
      else
        for m = 1, r.modules do robot:sensor{ kind = kind, module = m } end
      end
    elseif kind == "joint" then
      if at then
        robot:sensor{ kind = kind, joint = at }
      else
        for j = 1, #robot do robot:sensor{ kind = kind, joint = j } end
      end
    elseif at then
      robot:sensor{ kind = kind, module = at }
    else
      robot:sensor{ kind = kind }
    end
  end
  return robot
end

function P.joints(r)
  local out = {}
  for i, j in ipairs(P.chain(r):joints()) do out[i] = { index = j.index, role = j.role } end
  return out
end

function P.robot(r, path) written(P.chain(r):save(path)) end

function P.robot_name(path)
  local robot, message = gaitlab.robot.load(path)
  if not robot then error(message, 0) end
  return robot.name
end

function P.controller(c)
  local class
  if c.builtin then
    class = gaitlab.controllers[c.builtin]
  elseif c.template then
    class = gaitlab.controller.template(c.template)
  elseif c.stub then
    class = gaitlab.controller{ name = c.stub, step = function() end }
  else
    class = gaitlab.controller.load(c.file)
  end
  return class(c.params)
end

function P.params(c) return sorted_params(P.controller(c):params()) end

function P.drive(robot, groups)
  for _, g in ipairs(groups) do robot:group(g.joints):drive(P.controller(g.controller)) end
  return robot
end

function P.check_groups(r, groups) P.drive(P.chain(r), groups) end

function P.actuation(robot_file, groups, path)
  local robot, message = gaitlab.robot.load(robot_file)
  if not robot then error(message, 0) end
  written(P.drive(robot, groups):actuation():save(path))
end

function P.builtins()
  local names = {}
  for name in pairs(gaitlab.controllers) do names[#names + 1] = name end
  table.sort(names)
  return names
end

function P.templates()
  local names = gaitlab.controller.templates()
  table.sort(names)
  return names
end

function P.presets()
  local list = {}
  for name, preset in pairs(gaitlab.worlds) do
    list[#list + 1] = { name = name, description = preset.description,
                        params = sorted_params(preset.params) }
  end
  table.sort(list, function(a, b) return a.name < b.name end)
  return list
end

-- the preset's world; the start placement goes to a robot named `place` (a stand-in robot:
-- the environment file keeps only its name and pose)
function P.world(w, path)
  local world, start = gaitlab.worlds[w.preset](w.params)
  local place = w.place
  if place == "" and start and next(start) ~= nil then place = "robot" end
  if place ~= "" then world:add(gaitlab.robot.chain{ name = place, modules = 1 }, start) end
  if path then written(world:save(path)) end
end

-- checks a declaration, or (with `path`) that the written file loads and makes an instance
function P.new_controller(c, path)
  if path then
    gaitlab.controller.load(path){}
    return
  end
  local params = {}
  for _, p in ipairs(c.params) do
    params[p.name] = { p.value, min = p.min, max = p.max, unit = p.unit }
  end
  gaitlab.controller{ name = c.name, params = params, values = c.values,
                      step = function() end }{}
end

function P.template(name, path) written(gaitlab.controller.write_template(name, path)) end

function P.load_simulation(path)
  local sim, message = gaitlab.simulation.load(path)
  if not sim then error(message, 0) end
end
)lua";

// "bad argument #1 to 'chain' (MESSAGE)" -> "MESSAGE": the wizard and make name the thing
// themselves, the Lua function's name would mean nothing to their users
std::string unwrap(std::string message) {
    const std::string head = "bad argument #";
    if (message.rfind(head, 0) == 0 && !message.empty() && message.back() == ')') {
        const size_t open = message.find(" (");
        if (open != std::string::npos) return message.substr(open + 2, message.size() - open - 3);
    }
    return message;
}

// Lua literals of the choices

std::string lua_number(double v) {
    return number_text(v);
}

std::string lua_params(const ParamValues& params) {
    std::string out = "{";
    for (const auto& [name, value] : params)
        out += fmt::format("[{}] = {}, ", lua_quote(name), lua_number(value));
    return out + "}";
}

std::string lua_robot(const RobotChoice& r) {
    std::string sensors = "{";
    for (const SensorChoice& s : r.sensors) {
        sensors += fmt::format("{{ kind = {}, at = {} }}, ", lua_quote(s.kind),
                               s.at > 0 ? std::to_string(s.at) : "nil");
    }
    sensors += "}";
    return fmt::format("{{ name = {}, modules = {}, connection = {}, module = {}, sensors = {} }}",
                       lua_quote(r.name), r.modules, lua_quote(r.connection), lua_quote(r.module),
                       sensors);
}

std::string lua_controller(const ControllerChoice& c) {
    const char* key = c.kind == ControllerChoice::Kind::builtin     ? "builtin"
                      : c.kind == ControllerChoice::Kind::template_ ? "template"
                      : c.kind == ControllerChoice::Kind::stub      ? "stub"
                                                                    : "file";
    std::string name = c.name;
    if (c.kind == ControllerChoice::Kind::file) name = fs::absolute(name).string();
    return fmt::format("{{ {} = {}, params = {} }}", key, lua_quote(name), lua_params(c.params));
}

std::string lua_joints(const std::string& joints) {
    if (joints == "pitch" || joints == "yaw" || joints == "all" || joints == "roll")
        return lua_quote(joints);
    std::string out = "{";
    size_t start = 0;
    while (start < joints.size()) {
        size_t end = joints.find(' ', start);
        if (end == std::string::npos) end = joints.size();
        if (end > start) out += joints.substr(start, end - start) + ", ";
        start = end + 1;
    }
    return out + "}";
}

std::string lua_groups(const std::vector<GroupChoice>& groups) {
    std::string out = "{";
    for (const GroupChoice& g : groups) {
        out += fmt::format("{{ joints = {}, controller = {} }}, ", lua_joints(g.joints),
                           lua_controller(g.controller));
    }
    return out + "}";
}

std::string lua_world(const WorldChoice& w) {
    return fmt::format("{{ preset = {}, params = {}, place = {} }}", lua_quote(w.preset),
                       lua_params(w.params), lua_quote(w.place));
}

std::string lua_new_controller(const NewController& c) {
    std::string params = "{";
    for (const NewParam& p : c.params) {
        params += fmt::format("{{ name = {}, value = {}, min = {}, max = {}, unit = {} }}, ",
                              lua_quote(p.name), lua_number(p.value), lua_number(p.min),
                              lua_number(p.max), lua_quote(p.unit));
    }
    params += "}";
    std::string values = "{";
    for (const std::string& v : c.values)
        values += lua_quote(v) + ", ";
    values += "}";
    return fmt::format("{{ name = {}, params = {}, values = {} }}", lua_quote(c.name), params,
                       values);
}

// reading results back

std::string field_string(lua_State* L, int index, const char* key) {
    lua_getfield(L, index, key);
    std::string s = lua_isstring(L, -1) ? lua_tostring(L, -1) : "";
    lua_pop(L, 1);
    return s;
}

double field_number(lua_State* L, int index, const char* key) {
    lua_getfield(L, index, key);
    const double v = lua_isnumber(L, -1) ? lua_tonumber(L, -1) : 0;
    lua_pop(L, 1);
    return v;
}

std::vector<std::string> string_list(lua_State* L) {
    std::vector<std::string> out;
    const lua_Integer n = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        if (lua_isstring(L, -1)) out.emplace_back(lua_tostring(L, -1));
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    return out;
}

// the list of parameters on top of the stack (popped)
std::vector<ParamInfo> param_list(lua_State* L) {
    std::vector<ParamInfo> out;
    const lua_Integer n = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        out.push_back({field_string(L, -1, "name"), field_number(L, -1, "value"),
                       field_number(L, -1, "min"), field_number(L, -1, "max"),
                       field_string(L, -1, "unit")});
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    return out;
}

bool is_identifier(const std::string& s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    });
}

// Lua's reserved words cannot be written as `name = ...` in a table constructor
bool is_keyword(const std::string& s) {
    static const std::set<std::string> words{
        "and",      "break",  "do",   "else", "elseif", "end",  "false", "for",
        "function", "goto",   "if",   "in",   "local",  "nil",  "not",   "or",
        "repeat",   "return", "then", "true", "until",  "while"};
    return words.count(s) > 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// text

std::string lua_quote(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (std::isalnum(u) || std::string_view(" _-.,:/+=").find(c) != std::string_view::npos) {
            out += c;
        } else {
            out += fmt::format("\\{:03d}", u);
        }
    }
    return out + "\"";
}

std::string number_text(double v) {
    return fmt::format("{}", v);
}

bool parse_number(const std::string& text, double& out) {
    std::string t = text;
    if (!t.empty() && t[0] == '+') t.erase(0, 1);
    const char* end = t.data() + t.size();
    double v = 0;
    const auto r = std::from_chars(t.data(), end, v);
    if (t.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) return false;
    out = v;
    return true;
}

std::string parse_joints(const std::string& text, std::string& error) {
    std::string t;
    for (char c : text)
        t += c == ',' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const size_t first = t.find_first_not_of(' ');
    if (first == std::string::npos) {
        error = "no joints given (pitch, yaw, all, or joint numbers like 1 3 5)";
        return "";
    }
    t = t.substr(first, t.find_last_not_of(' ') - first + 1);
    if (t == "pitch" || t == "yaw" || t == "all") return t;
    std::string out;
    size_t start = 0;
    while (start <= t.size()) {
        size_t end = t.find(' ', start);
        if (end == std::string::npos) end = t.size();
        const std::string word = t.substr(start, end - start);
        start = end + 1;
        if (word.empty()) continue;
        if (word == "pitch" || word == "yaw" || word == "all") {
            error = fmt::format(
                "'{}' stands alone: say pitch, yaw or all, or joint numbers like "
                "1 3 5, not both (got '{}')",
                word, t);
            return "";
        }
        int n = 0;
        const auto r = std::from_chars(word.data(), word.data() + word.size(), n);
        if (r.ec != std::errc() || r.ptr != word.data() + word.size() || n < 1) {
            error = fmt::format(
                "'{}' is not a joint: say pitch, yaw, all, or joint numbers from 1 like 1 3 5{}",
                word, did_you_mean(word, {"pitch", "yaw", "all"}));
            return "";
        }
        out += (out.empty() ? "" : " ") + std::to_string(n);
    }
    return out;
}

ParamValues parse_params(const std::string& text) {
    ParamValues out;
    std::string item;
    const auto flush = [&] {
        if (item.empty()) return;
        const size_t eq = item.find('=');
        double v = 0;
        if (eq == std::string::npos || eq == 0 || !parse_number(item.substr(eq + 1), v)) {
            throw Error(
                fmt::format("'{}': NAME=VALUE expected, the value a number (e.g. "
                            "amplitude=30)",
                            item));
        }
        const std::string name = item.substr(0, eq);
        // (the last would win without a word: say which is meant)
        for (const auto& [seen, value] : out) {
            if (seen == name) {
                throw Error(fmt::format("'{}' is given twice ({}={} and {}): give it once", name,
                                        name, number_text(value), item));
            }
        }
        out.emplace_back(name, v);
        item.clear();
    };
    for (char c : text) {
        if (c == ' ' || c == ',' || c == ':' || c == '\t') {
            flush();
        } else {
            item += c;
        }
    }
    flush();
    return out;
}

SensorChoice parse_sensor(const std::string& text) {
    SensorChoice s;
    const size_t colon = text.find(':');
    s.kind = text.substr(0, colon);
    if (colon != std::string::npos) {
        const std::string n = text.substr(colon + 1);
        const auto r = std::from_chars(n.data(), n.data() + n.size(), s.at);
        if (n.empty() || r.ec != std::errc() || r.ptr != n.data() + n.size() || s.at < 1) {
            throw Error(fmt::format(
                "sensor '{}': KIND or KIND:N expected, N a module (or joint) number from 1", text));
        }
    }
    const std::vector<std::string> kinds{"joint", "imu", "contact", "range", "position"};
    if (std::find(kinds.begin(), kinds.end(), s.kind) == kinds.end()) {
        throw Error(
            fmt::format("unknown sensor kind '{}'{} (kinds: joint, imu, contact, range, "
                        "position)",
                        s.kind, did_you_mean(s.kind, kinds)));
    }
    if (s.kind == "position" && s.at > 0) {
        throw Error("sensor 'position': it measures the whole robot, so it takes no :N");
    }
    return s;
}

ControllerChoice parse_controller(const std::string& text) {
    ControllerChoice c;
    const std::string prefix = "template/";
    if (text.rfind(prefix, 0) == 0) {
        c.kind = ControllerChoice::Kind::template_;
        c.name = text.substr(prefix.size());
    } else if (text.size() > 4 && text.compare(text.size() - 4, 4, ".lua") == 0) {
        c.kind = ControllerChoice::Kind::file;
        c.name = text;
    } else {
        c.kind = ControllerChoice::Kind::builtin;
        c.name = text;
    }
    if (c.name.empty()) throw Error("no controller named");
    return c;
}

GroupChoice parse_group(const std::string& text) {
    const std::string form =
        "JOINTS=CONTROLLER[:PARAM=VALUE...] expected, e.g. pitch=sine:amplitude=40:phase=-120";
    const size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
        throw Error(fmt::format("group '{}': {}", text, form));
    }
    GroupChoice g;
    std::string error;
    g.joints = parse_joints(text.substr(0, eq), error);
    if (g.joints.empty()) throw Error(fmt::format("group '{}': {}", text, error));
    const std::string rest = text.substr(eq + 1);
    const size_t colon = rest.find(':');
    g.controller = parse_controller(rest.substr(0, colon));
    if (colon != std::string::npos) {
        try {
            g.controller.params = parse_params(rest.substr(colon + 1));
        } catch (const Error& e) {
            throw Error(fmt::format("group '{}': {}", text, e.what()));
        }
    }
    return g;
}

// ---------------------------------------------------------------------------------------------
// PartMaker

PartMaker::PartMaker() : host_(std::make_unique<scripting::LuaHost>()) {
    scripting::RecordSettings rec;
    rec.disabled = true;
    host_->set_recording(rec);
    host_->run_string(kHelpers, std::string("=") + kChunk);
}

PartMaker::~PartMaker() = default;

void PartMaker::eval(const std::string& code, int nresults) {
    lua_State* L = host_->state();
    const std::string chunk = "local P = gaitlab_parts\n" + code;
    if (luaL_loadbuffer(L, chunk.data(), chunk.size(), (std::string("=") + kChunk).c_str()) !=
        LUA_OK) {
        const std::string message = lua_tostring(L, -1);
        lua_pop(L, 1);
        throw Error(message);
    }
    try {
        scripting::protected_call(L, 0, nresults);
    } catch (const scripting::ScriptError& e) {
        std::string message = e.what();
        // the place is this file's helpers, which the user never sees: "gaitlab make:LINE: "
        const std::string here = std::string(kChunk) + ":";
        if (message.rfind(here, 0) == 0) {
            const size_t end = message.find_first_not_of("0123456789", here.size());
            if (end != std::string::npos && end > here.size() && message.compare(end, 2, ": ") == 0)
                message.erase(0, end + 2);
        }
        throw Error(unwrap(message));
    }
}

std::vector<std::string> PartMaker::builtins() {
    eval("return P.builtins()", 1);
    return string_list(host_->state());
}

std::vector<std::string> PartMaker::templates() {
    eval("return P.templates()", 1);
    return string_list(host_->state());
}

std::vector<PresetInfo> PartMaker::presets() {
    eval("return P.presets()", 1);
    lua_State* L = host_->state();
    std::vector<PresetInfo> out;
    const lua_Integer n = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        PresetInfo p;
        p.name = field_string(L, -1, "name");
        p.description = field_string(L, -1, "description");
        lua_getfield(L, -1, "params");
        p.params = param_list(L);
        lua_pop(L, 1);
        out.push_back(std::move(p));
    }
    lua_pop(L, 1);
    return out;
}

std::vector<ParamInfo> PartMaker::controller_params(const ControllerChoice& c) {
    check_controller(c);
    ControllerChoice defaults = c;
    defaults.params.clear();
    eval("return P.params(" + lua_controller(defaults) + ")", 1);
    return param_list(host_->state());
}

void PartMaker::check_robot(const RobotChoice& robot) {
    eval("P.chain(" + lua_robot(robot) + ")", 0);
}

std::vector<JointInfo> PartMaker::joints(const RobotChoice& robot) {
    eval("return P.joints(" + lua_robot(robot) + ")", 1);
    lua_State* L = host_->state();
    std::vector<JointInfo> out;
    const lua_Integer n = luaL_len(L, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        out.push_back(
            {static_cast<int>(field_number(L, -1, "index")), field_string(L, -1, "role")});
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    return out;
}

void PartMaker::check_controller(const ControllerChoice& c) {
    if (c.kind == ControllerChoice::Kind::builtin) {
        const std::vector<std::string> names = builtins();
        if (std::find(names.begin(), names.end(), c.name) == names.end()) {
            throw Error(
                fmt::format("unknown controller '{}'{} (built-in controllers: {}; a "
                            "template is template/NAME, a Lua controller file PATH.lua)",
                            c.name, did_you_mean(c.name, names), fmt::join(names, ", ")));
        }
    } else if (c.kind == ControllerChoice::Kind::template_) {
        const std::vector<std::string> names = templates();
        if (std::find(names.begin(), names.end(), c.name) == names.end()) {
            throw Error(fmt::format("unknown template '{}'{} (templates: {})", c.name,
                                    did_you_mean(c.name, names), fmt::join(names, ", ")));
        }
    }
    eval("P.controller(" + lua_controller(c) + ")", 0);
}

void PartMaker::check_groups(const RobotChoice& robot, const std::vector<GroupChoice>& groups) {
    for (const GroupChoice& g : groups)
        check_controller(g.controller);
    eval("P.check_groups(" + lua_robot(robot) + ", " + lua_groups(groups) + ")", 0);
}

void PartMaker::check_new_controller(const NewController& c) {
    if (is_keyword(c.name)) {
        throw Error(
            fmt::format("'{}' is a word Lua keeps for itself: choose another name", c.name));
    }
    if (!is_identifier(c.name)) {
        throw Error(
            fmt::format("'{}' cannot name a controller: letters, digits and _, not "
                        "starting with a digit (e.g. my_gait)",
                        c.name));
    }
    std::set<std::string> seen;
    const auto check_name = [&](const std::string& n, const char* what) {
        if (is_keyword(n)) {
            throw Error(fmt::format("'{}' is a word Lua keeps for itself: choose another name", n));
        }
        if (!is_identifier(n)) {
            throw Error(
                fmt::format("'{}' cannot name a {}: letters, digits and _, not starting "
                            "with a digit (e.g. amplitude)",
                            n, what));
        }
        if (!seen.insert(n).second) {
            throw Error(fmt::format("'{}' is already a parameter or value of the controller", n));
        }
    };
    for (const NewParam& p : c.params) {
        check_name(p.name, "parameter");
        // the unit goes into the file, in a string and a comment: one line of visible text
        if (std::any_of(p.unit.begin(), p.unit.end(), [](char ch) {
                return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
            })) {
            throw Error(
                fmt::format("the unit of '{}' has a control character: type plain text", p.name));
        }
    }
    for (const std::string& v : c.values)
        check_name(v, "value");
    eval("P.new_controller(" + lua_new_controller(c) + ")", 0);
}

void PartMaker::check_world(const WorldChoice& world) {
    std::vector<std::string> names;
    for (const PresetInfo& p : presets())
        names.push_back(p.name);
    if (std::find(names.begin(), names.end(), world.preset) == names.end()) {
        throw Error(fmt::format("unknown world '{}'{} (worlds: {})", world.preset,
                                did_you_mean(world.preset, names), fmt::join(names, ", ")));
    }
    eval("P.world(" + lua_world(world) + ")", 0);
}

void PartMaker::check_sim(const SimChoice& sim) {
    SimulationOptions o;
    o.dt = sim.dt;
    o.control_every = sim.control_every;
    o.solver_iterations = sim.solver_iterations;
    validate(o);
    // the simulation file's own check (read_simulation): what a file takes, make takes
    checked_ticks("duration", sim.duration, o.dt);
}

void PartMaker::write_robot(const RobotChoice& robot, const std::string& path) {
    eval("P.robot(" + lua_robot(robot) + ", " + lua_quote(fs::absolute(path).string()) + ")", 0);
}

std::string PartMaker::robot_name(const std::string& robot_file) {
    eval("return P.robot_name(" + lua_quote(fs::absolute(robot_file).string()) + ")", 1);
    lua_State* L = host_->state();
    std::string name = lua_tostring(L, -1);
    lua_pop(L, 1);
    return name;
}

void PartMaker::write_actuation(const std::string& robot_file,
                                const std::vector<GroupChoice>& groups, const std::string& path) {
    for (const GroupChoice& g : groups)
        check_controller(g.controller);
    eval("P.actuation(" + lua_quote(fs::absolute(robot_file).string()) + ", " + lua_groups(groups) +
             ", " + lua_quote(fs::absolute(path).string()) + ")",
         0);
}

void PartMaker::write_world(const WorldChoice& world, const std::string& path) {
    check_world(world);
    eval("P.world(" + lua_world(world) + ", " + lua_quote(fs::absolute(path).string()) + ")", 0);
}

void PartMaker::write_sim(const SimChoice& sim, const std::string& robot_file,
                          const std::string& actuation_file, const std::string& world_file,
                          const std::string& path) {
    check_sim(sim);
    SimulationFile f;
    f.name = sim.name;
    f.duration = sim.duration;
    f.options.dt = sim.dt;
    f.options.control_every = sim.control_every;
    f.options.solver_iterations = sim.solver_iterations;
    f.environment = relative_path(world_file, path);
    f.robots.push_back({relative_path(robot_file, path),
                        actuation_file.empty() ? "" : relative_path(actuation_file, path), 0});
    f.record.enabled = sim.record;
    // written next to `path` (its relative names hold there), loaded, then renamed: only a
    // simulation file that loads is ever written
    const fs::path target = fs::absolute(path);
    const std::string check =
        (target.parent_path() / fmt::format(".{}.check-{}.xml", target.stem().string(), getpid()))
            .string();
    gaitlab::write_simulation(check, f);
    try {
        eval("P.load_simulation(" + lua_quote(check) + ")", 0);
    } catch (const Error& e) {
        std::remove(check.c_str());
        std::string message = e.what();
        for (size_t at = message.find(check); at != std::string::npos;
             at = message.find(check, at + path.size()))
            message.replace(at, check.size(), path);
        throw Error(message);
    }
    std::error_code ec;
    fs::rename(check, target, ec);
    if (ec) {
        std::remove(check.c_str());
        throw IoError(fmt::format("{}: cannot write the file: {}", path, ec.message()));
    }
}

void PartMaker::write_new_controller(const NewController& c, const std::string& path) {
    check_new_controller(c);
    std::set<std::string> taken;
    for (const NewParam& p : c.params)
        taken.insert(p.name);
    for (const std::string& v : c.values)
        taken.insert(v);
    std::string clock = "elapsed";
    while (taken.count(clock))
        clock += "_";

    std::string text = fmt::format(
        "-- {1}: the controller {0}, made by `gaitlab new`. Write your gait in step()\n"
        "-- below; a simulation that is running picks up the file again when you save it\n"
        "-- (docs/lua-controllers.md).\n"
        "return gaitlab.controller{{\n"
        "  name = \"{0}\",\n"
        "  params = {{                                 -- {{ initial value, min =, max =, unit "
        "= }}\n",
        c.name, fs::path(path).filename().string());
    std::string param_names, value_names;
    for (const NewParam& p : c.params) {
        text += fmt::format("    {} = {{ {}, min = {}, max = {}, unit = {} }},\n", p.name,
                            number_text(p.value), number_text(p.min), number_text(p.max),
                            lua_quote(p.unit));
        param_names += fmt::format("{}self.{}{}", param_names.empty() ? "" : ", ", p.name,
                                   p.unit.empty() ? "" : " (" + p.unit + ")");
    }
    std::string values;
    for (const std::string& v : c.values) {
        values += fmt::format("{}\"{}\"", values.empty() ? "" : ", ", v);
        value_names += fmt::format("{}self.{}[m]", value_names.empty() ? "" : ", ", v);
    }
    text +=
        fmt::format("  }},\n  values = {{ {} }},  -- per joint: recorded and plottable\n", values);
    text += fmt::format(
        "  step = function(self, dt)                  -- every control tick, dt seconds apart\n"
        "    -- Your parameters: {0}.\n"
        "    -- Your per-joint values: {1}.\n"
        "    -- Replace the lines below with your gait. As written they send a sine wave (40 deg,\n"
        "    -- 0.5 Hz, 120 deg between neighbours) along the group, so the robot moves already.\n"
        "    self.{2} = (self.{2} or 0) + dt  -- seconds since the start\n"
        "    for m = 1, self.joints do            -- joint 1 is nearest the tail\n"
        "      local angle = 40 * math.sin(2 * math.pi * 0.5 * self.{2} + (m - 1) * "
        "math.rad(120))\n",
        param_names.empty() ? "none" : param_names, value_names.empty() ? "none" : value_names,
        clock);
    for (const std::string& v : c.values) {
        if (v == "time") text += "      self.time[m] = self.time[m] + dt\n";
        if (v == "angle") text += "      self.angle[m] = angle\n";
    }
    text +=
        "      self:set_angle(m, angle)           -- where joint m should go, deg\n"
        "    end\n"
        "  end,\n"
        "}\n";
    write_file_atomic(path, text);
    eval("P.new_controller(nil, " + lua_quote(fs::absolute(path).string()) + ")", 0);
}

void PartMaker::write_template(const std::string& name, const std::string& path) {
    eval("P.template(" + lua_quote(name) + ", " + lua_quote(fs::absolute(path).string()) + ")", 0);
}

}  // namespace gaitlab::cli
