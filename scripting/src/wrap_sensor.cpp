// gaitlab.sensor, robot:sensor{...}, robot:sensors() and sensor handles.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "lua_util.h"
#include "scene.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

using RobotPtr = std::shared_ptr<RobotBinding>;

/// A sensor of a robot: the robot and the sensor's index among its sensors.
struct SensorHandle {
    RobotPtr robot;
    int k = 0;

    const SensorSpec& spec() const { return robot->spec.sensors[static_cast<size_t>(k)]; }
};

// a sensor is named by its robot and its number (sensors are only ever added)
HandleKey handle_key(const SensorHandle& s) {
    return {s.robot.get(), std::to_string(s.k)};
}

SensorHandle& check_sensor(lua_State* L, int index) {
    return check_object<SensorHandle>(L, index, kSensorType);
}

// every key of robot:sensor{...}, and those each kind takes
const std::vector<std::string> kAllKeys = {"kind", "name",      "module",    "joint",
                                           "half", "direction", "max_range", "enabled"};

std::vector<std::string> keys_of(SensorKind kind) {
    switch (kind) {
        case SensorKind::joint:
            return {"kind", "name", "joint", "enabled"};
        case SensorKind::imu:
            return {"kind", "name", "module", "half", "enabled"};
        case SensorKind::contact:
            return {"kind", "name", "module", "enabled"};
        case SensorKind::range:
            return {"kind", "name", "module", "half", "direction", "max_range", "enabled"};
        case SensorKind::position:
            return {"kind", "name", "enabled"};
    }
    return {};
}

// "'a', 'b' or 'c'"
std::string quoted_list(const std::vector<std::string>& names) {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
        out += "'" + names[i] + "'";
    }
    return out;
}

SensorKind parse_kind(const std::string& name) {
    const auto& names = sensor_kind_names();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        throw Error(fmt::format("unknown sensor kind '{}'{} (expected {})", name,
                                did_you_mean(name, names), quoted_list(names)));
    }
    return parse_sensor_kind(name);
}

// a 1-based module or joint number field that must be there, as a 0-based index. Whether the
// robot has it is validate_sensor's to say (it checks the number before the name made of it);
// here only what the engine cannot see: a value that is no number, or one that is no int (a
// fraction, nan, a whole number beyond int's range, which must not wrap on the way to it)
int required_index(const Fields& f, const char* key, const char* what) {
    lua_State* L = f.state();
    const bool number = f.push(key) == LUA_TNUMBER;
    int exact = 0;
    const lua_Integer v = lua_tointegerx(L, -1, &exact);
    const double d = lua_tonumber(L, -1);
    const std::string type = type_name(L, -1);
    lua_pop(L, 1);
    // not a numeric string either ("3"), as no integer field takes one (read_integer)
    if (!number) f.fail(key, fmt::format("{} number expected, got {}", what, type));
    // the index, the number - 1, is an int
    constexpr double kLowest = std::numeric_limits<int>::min() + 1.0;
    constexpr double kHighest = std::numeric_limits<int>::max();
    if (std::isfinite(d) && std::floor(d) == d && (d < kLowest || d > kHighest)) {
        f.fail(key, fmt::format("{} number out of range, got {}", what,
                                exact ? fmt::format("{}", v) : fmt::format("{}", d)));
    }
    return static_cast<int>(f.integer(key, 0) - 1);  // fails for a fraction, nan and inf
}

// builds a sensor spec from the table at index 2 (argument #1 of the method)
SensorSpec sensor_from_table(lua_State* L) {
    const int arg = 2;
    check_table(L, arg);
    if (raw_getfield(L, arg, "kind") != LUA_TSTRING) {
        const std::string t = type_name(L, -1);
        lua_pop(L, 1);
        throw ArgError(arg, fmt::format("field 'kind': sensor kind expected ({}), got {}",
                                        quoted_list(sensor_kind_names()), t));
    }
    const std::string kind_name = to_string(L, -1);
    lua_pop(L, 1);
    SensorSpec s;
    try {
        s.kind = parse_kind(kind_name);
    } catch (const Error& e) {
        throw ArgError(arg, e.what());
    }

    Fields f(L, arg, arg,
             {"kind", "name", "module", "joint", "half", "direction", "max_range", "enabled"});
    // keys that exist, but not for this kind
    const std::vector<std::string> own = keys_of(s.kind);
    for (const std::string& key : kAllKeys) {
        if (f.has(key.c_str()) && std::find(own.begin(), own.end(), key) == own.end()) {
            throw ArgError(
                arg, fmt::format("key '{}' does not apply to {} sensors (their keys: {})", key,
                                 kind_name, fmt::join(own, ", ")));
        }
    }
    s.name = f.string("name", "");
    s.enabled = f.boolean("enabled", true);
    switch (s.kind) {
        case SensorKind::joint:
            s.joint = required_index(f, "joint", "joint");
            break;
        case SensorKind::imu:
        case SensorKind::contact:
        case SensorKind::range:
            s.module = required_index(f, "module", "module");
            break;
        case SensorKind::position:
            break;
    }
    if (f.has("half")) {
        const std::string half = f.string("half", "");
        if (half != "tail" && half != "head") {
            const std::vector<std::string> halves = {"tail", "head"};
            f.fail("half", fmt::format("unknown module half '{}'{} (expected 'tail' or 'head')",
                                       half, did_you_mean(half, halves)));
        }
        s.half = parse_module_half(half);
    }
    s.direction = f.vec3("direction", s.direction);
    s.max_range = f.number("max_range", s.max_range);
    return s;
}

// pushes the handle of the robot's sensor k: one per sensor (see push_canonical)
void push_handle(lua_State* L, RobotPtr robot, int k) {
    push_canonical<SensorHandle>(L, kSensorType, SensorHandle{std::move(robot), k});
}

int sensor_eq(lua_State* L) {
    return handle_eq<SensorHandle>(L, kSensorType);
}

std::vector<std::string> sensor_names(const RobotSpec& robot) {
    std::vector<std::string> names;
    for (const SensorSpec& s : robot.sensors)
        names.push_back(sensor_name(s));
    return names;
}

// pushes the readings as { channel = value } in user units (degrees; booleans for on/off)
void push_readings(lua_State* L, SensorKind kind, const double* values) {
    const auto& channels = sensor_channels(kind);
    lua_createtable(L, 0, static_cast<int>(channels.size()));
    for (size_t c = 0; c < channels.size(); ++c) {
        if (channels[c].boolean) {
            lua_pushboolean(L, values[c] != 0);
        } else {
            lua_pushnumber(L, to_user_units(channels[c], values[c]));
        }
        lua_setfield(L, -2, channels[c].name.c_str());
    }
}

void push_channels(lua_State* L, SensorKind kind) {
    const auto& channels = sensor_channels(kind);
    lua_createtable(L, static_cast<int>(channels.size()), 0);
    for (size_t c = 0; c < channels.size(); ++c) {
        lua_createtable(L, 0, 2);
        lua_pushstring(L, channels[c].name.c_str());
        lua_setfield(L, -2, "name");
        const std::string unit = channels[c].boolean ? "boolean" : user_unit(channels[c]);
        lua_pushstring(L, unit.c_str());
        lua_setfield(L, -2, "unit");
        lua_rawseti(L, -2, static_cast<lua_Integer>(c + 1));
    }
}

int sensor_read(lua_State* L) {
    return protect(L, [&] {
        SensorHandle& h = check_sensor(L, 1);
        auto sim = h.robot->live();
        const int i = sim->sensor_index(h.robot->index, h.k);
        if (!sim->sensor_enabled(i)) {
            lua_pushnil(L);
            return 1;
        }
        push_readings(L, h.spec().kind, sim->sensor_values(i).data());
        return 1;
    });
}

int sensor_set(lua_State* L, bool on) {
    return protect(L, [&] {
        SensorHandle& h = check_sensor(L, 1);
        h.robot->set_sensor_enabled(h.k, on, opt_origin(L, 2));
        lua_settop(L, 1);
        return 1;
    });
}

int sensor_on(lua_State* L) {
    return sensor_set(L, true);
}

int sensor_off(lua_State* L) {
    return sensor_set(L, false);
}

int sensor_channels_method(lua_State* L) {
    return protect(L, [&] {
        push_channels(L, check_sensor(L, 1).spec().kind);
        return 1;
    });
}

const std::vector<std::string> kFields = {"name", "kind",      "module",    "joint",
                                          "half", "direction", "max_range", "enabled"};

int sensor_index(lua_State* L) {
    return protect(L, [&] {
        SensorHandle& h = check_sensor(L, 1);
        const SensorSpec& s = h.spec();
        const std::string key = check_string(L, 2);
        const bool on_module = s.kind == SensorKind::imu || s.kind == SensorKind::contact ||
                               s.kind == SensorKind::range;
        const bool mounted = s.kind == SensorKind::imu || s.kind == SensorKind::range;
        if (key == "name") {
            lua_pushstring(L, sensor_name(s).c_str());
        } else if (key == "kind") {
            lua_pushstring(L, to_string(s.kind));
        } else if (key == "enabled") {
            lua_pushboolean(L, s.enabled);
        } else if (key == "module") {
            if (on_module) {
                lua_pushinteger(L, s.module + 1);
            } else {
                lua_pushnil(L);
            }
        } else if (key == "joint") {
            if (s.kind == SensorKind::joint) {
                lua_pushinteger(L, s.joint + 1);
            } else {
                lua_pushnil(L);
            }
        } else if (key == "half") {
            if (mounted) {
                lua_pushstring(L, to_string(s.half));
            } else {
                lua_pushnil(L);
            }
        } else if (key == "direction" || key == "max_range") {
            if (s.kind != SensorKind::range) {
                lua_pushnil(L);
            } else if (key == "direction") {
                push_vec3(L, s.direction);
            } else {
                lua_pushnumber(L, s.max_range);
            }
        } else if (raw_getfield(L, lua_upvalueindex(1), key) == LUA_TNIL) {
            std::vector<std::string> names = kFields;
            for (const char* m : {"read", "on", "off", "channels"})
                names.emplace_back(m);
            throw Error(fmt::format("sensor '{}' has no field or method '{}'{}", sensor_name(s),
                                    key, did_you_mean(key, names)));
        }
        return 1;
    });
}

int sensor_newindex(lua_State* L) {
    return protect(L, [&] {
        SensorHandle& h = check_sensor(L, 1);
        const std::string key = check_string(L, 2);
        const std::string name = sensor_name(h.spec());
        if (key == "enabled") {
            if (!lua_isboolean(L, 3)) {
                throw Error(fmt::format("sensor '{}': enabled must be a boolean, got {}", name,
                                        type_name(L, 3)));
            }
            h.robot->set_sensor_enabled(h.k, lua_toboolean(L, 3), default_origin(L));
            return 0;
        }
        if (std::find(kFields.begin(), kFields.end(), key) != kFields.end()) {
            throw Error(
                fmt::format("sensor '{}': '{}' cannot be changed (only 'enabled' can)", name, key));
        }
        throw Error(
            fmt::format("sensor '{}' has no field '{}'{}", name, key, did_you_mean(key, kFields)));
    });
}

int sensor_tostring(lua_State* L) {
    return protect(L, [&] {
        SensorHandle& h = check_sensor(L, 1);
        const SensorSpec& s = h.spec();
        std::string where;
        switch (s.kind) {
            case SensorKind::joint:
                where = fmt::format(" on joint {}", s.joint + 1);
                break;
            case SensorKind::contact:
                where = fmt::format(" on module {}", s.module + 1);
                break;
            case SensorKind::imu:
            case SensorKind::range:
                where = fmt::format(" on module {} ({} half)", s.module + 1, to_string(s.half));
                break;
            case SensorKind::position:
                break;
        }
        const std::string text = fmt::format("gaitlab.Sensor '{}' ({}{}, {})", sensor_name(s),
                                             to_string(s.kind), where, s.enabled ? "on" : "off");
        lua_pushstring(L, text.c_str());
        return 1;
    });
}

// gaitlab.sensor.channels(kind)
int channels_of_kind(lua_State* L) {
    return protect(L, [&] {
        const std::string kind = check_string(L, 1);
        try {
            push_channels(L, parse_kind(kind));
        } catch (const Error& e) {
            throw ArgError(1, e.what());
        }
        return 1;
    });
}

}  // namespace

int robot_sensor(lua_State* L) {
    return protect(L, [&] {
        RobotPtr& robot = check_object<RobotPtr>(L, 1, kRobotType);
        if (lua_type(L, 2) == LUA_TSTRING) {
            const std::string name = to_string(L, 2);
            const std::vector<std::string> names = sensor_names(robot->spec);
            const auto it = std::find(names.begin(), names.end(), name);
            if (it == names.end()) {
                throw ArgError(2, fmt::format("robot '{}' has no sensor '{}'{}{}", robot->spec.name,
                                              name, did_you_mean(name, names),
                                              names.empty() ? " (it has no sensors)"
                                                            : fmt::format(" (its sensors: {})",
                                                                          fmt::join(names, ", "))));
            }
            push_handle(L, robot, static_cast<int>(it - names.begin()));
            return 1;
        }
        if (!lua_istable(L, 2)) {
            throw ArgError(2, "sensor table or sensor name expected, got " + type_name(L, 2));
        }
        SensorSpec spec = sensor_from_table(L);
        try {
            validate_sensor(robot->spec, spec);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        if (spec.name.empty()) spec.name = default_sensor_name(spec);
        const int k = robot->attach(std::move(spec));
        push_handle(L, robot, k);
        return 1;
    });
}

int robot_sensors(lua_State* L) {
    return protect(L, [&] {
        RobotPtr& robot = check_object<RobotPtr>(L, 1, kRobotType);
        const int n = static_cast<int>(robot->spec.sensors.size());
        lua_createtable(L, n, 0);
        for (int k = 0; k < n; ++k) {
            push_handle(L, robot, k);
            lua_rawseti(L, -2, k + 1);
        }
        return 1;
    });
}

void open_sensor(lua_State* L) {
    const luaL_Reg methods[] = {{"read", sensor_read},
                                {"on", sensor_on},
                                {"off", sensor_off},
                                {"channels", sensor_channels_method},
                                {nullptr, nullptr}};
    const luaL_Reg meta[] = {{"__newindex", sensor_newindex},
                             {"__tostring", sensor_tostring},
                             {"__eq", sensor_eq},
                             {nullptr, nullptr}};
    register_type_with_fields<SensorHandle>(L, kSensorType, methods, sensor_index, meta);

    // gaitlab.sensor = { kinds = {...}, channels = function(kind) }
    lua_newtable(L);
    const auto& kinds = sensor_kind_names();
    lua_createtable(L, static_cast<int>(kinds.size()), 0);
    for (size_t i = 0; i < kinds.size(); ++i) {
        lua_pushstring(L, kinds[i].c_str());
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
    lua_setfield(L, -2, "kinds");
    lua_pushcfunction(L, channels_of_kind);
    lua_setfield(L, -2, "channels");
    lua_setfield(L, -2, "sensor");
}

}  // namespace gaitlab::scripting
