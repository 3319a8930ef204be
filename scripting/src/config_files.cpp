#include "config_files.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <filesystem>
#include <set>
#include <system_error>

#include <fmt/format.h>

#include "gaitlab/controllers/registry.h"
#include "gaitlab/files.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/suggest.h"
#include "hot_reload.h"
#include "lua_controller.h"
#include "lua_util.h"
#include "recording.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace fs = std::filesystem;

namespace {

// an error at the place a reference was read (plain SpecError when it was made in code)
[[noreturn]] void fail_at(const ControllerRef& ref, const std::string& message) {
    if (ref.source.empty()) throw SpecError(message);
    throw FormatError(fmt::format("{}:{}: {}", ref.source, ref.line, message), ref.source,
                      ref.line);
}

// the class push_file_class or push_template_class left on the stack (popped)
std::shared_ptr<LuaControllerClass> class_on_top(lua_State* L) {
    auto* p = static_cast<std::shared_ptr<LuaControllerClass>*>(
        luaL_testudata(L, -1, kControllerClassType));
    if (!p) throw Error("internal error: no controller class on the Lua stack");
    auto cls = *p;
    lua_pop(L, 1);
    return cls;
}

// `name` as part of a file name: ASCII letters, digits, '-', '_' and non-ASCII UTF-8 (names are
// valid UTF-8) kept, anything else ('/', '.', '\\', spaces, quotes ...) as '_', at most 64
// bytes (cut between characters), never empty, unique among `taken` (adds '_2', ...): whatever
// a robot is called, its parts stay inside the folder they are saved to, one file each
std::string file_name_part(const std::string& name, std::set<std::string>& taken) {
    std::string out;
    for (const char ch : name) {
        const auto c = static_cast<unsigned char>(ch);
        const bool keep = std::isalnum(c) || c == '-' || c == '_' || c >= 0x80;
        out += keep ? ch : '_';
    }
    if (out.size() > 64) {
        size_t cut = 64;
        while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xc0) == 0x80)
            --cut;  // not inside a UTF-8 sequence
        out.resize(cut);
    }
    if (out.empty()) out = "robot";
    std::string unique = out;
    for (int k = 2; !taken.insert(unique).second; ++k)
        unique = fmt::format("{}_{}", out, k);
    return unique;
}

}  // namespace

std::string checked_input_path(lua_State* L, const std::string& arg) {
    // input_path copies the file for the run folders as it names it: check what it would copy
    const std::string path = Recordings::of(L).input_path(script_path(L, arg));
    try {
        check_file(path);
    } catch (const ReadError& e) {
        throw FormatError(fmt::format("{}: cannot read the file: {}", path, e.reason()), path, 0);
    }
    return input_path(L, arg);
}

std::shared_ptr<Controller> make_controller(lua_State* L, const ControllerRef& ref) {
    std::shared_ptr<Controller> c;
    try {
        switch (ref.kind) {
            case ControllerRef::Kind::builtin: {
                c = controllers::make_builtin(ref.name);
                if (!c) {
                    const std::vector<std::string> names = controllers::builtin_names();
                    fail_at(ref, fmt::format("unknown built-in controller '{}'{} (built-ins: {})",
                                             ref.name, did_you_mean(ref.name, names),
                                             fmt::join(names, ", ")));
                }
                break;
            }
            case ControllerRef::Kind::file: {
                const std::string path =
                    ref.source.empty() ? ref.name : resolve_path(ref.source, ref.name);
                std::error_code ec;
                // a replay has the code even where the file is gone
                if (!fs::is_regular_file(path, ec) && !Reloader::of(L).has_override()) {
                    fail_at(ref, fs::exists(path, ec)
                                     ? fmt::format("controller file {} is not a regular file "
                                                   "(a folder, FIFO or device)",
                                                   path)
                                     : fmt::format("no controller file at {}", path));
                }
                push_file_class(L, path, true);
                c = std::make_shared<LuaController>(L, class_on_top(L));
                break;
            }
            case ControllerRef::Kind::template_:
                push_template_class(L, ref.name);
                c = std::make_shared<LuaController>(L, class_on_top(L));
                break;
        }
    } catch (const FormatError&) {
        throw;
    } catch (const ScriptError&) {
        throw;  // names the Lua file and line itself
    } catch (const Error& e) {
        fail_at(ref, e.what());
    }
    std::vector<std::string> names;
    for (const ParamDef& p : c->def().params)
        names.push_back(p.name);
    for (const auto& [name, value] : ref.params) {
        const int i = c->find_param(name);
        if (i < 0) {
            fail_at(ref, fmt::format("controller '{}' has no parameter '{}'{} (parameters: {})",
                                     c->name(), name, did_you_mean(name, names),
                                     fmt::join(names, ", ")));
        }
        try {
            c->set_param(i, value);
        } catch (const SpecError& e) {
            fail_at(ref, e.what());
        }
    }
    return c;
}

std::vector<std::shared_ptr<Controller>> actuate(lua_State* L, RobotBinding& robot,
                                                 const ActuationSpec& spec) {
    std::vector<std::vector<int>> groups;
    std::vector<std::shared_ptr<Controller>> made;
    for (const GroupSpec& g : spec.groups) {
        try {
            groups.push_back(resolve_group(g, robot.spec));
        } catch (const SpecError& e) {
            fail_at(g.controller, fmt::format("group {}: {}", groups.size() + 1, e.what()));
        }
        made.push_back(make_controller(L, g.controller));
        // the same joints twice, in this file or with what already drives the robot
        Actuation planned = robot.drives;
        for (size_t i = 0; i + 1 < made.size(); ++i)
            planned.push_back({groups[i], made[i]});
        try {
            check_new_group(planned, {groups.back(), made.back()}, robot.spec.name);
        } catch (const SpecError& e) {
            fail_at(g.controller, fmt::format("group {}: {}", groups.size(), e.what()));
        }
    }
    for (size_t i = 0; i < made.size(); ++i)
        robot.drive(groups[i], made[i]);
    return made;
}

ActuationSpec actuation_of(const RobotBinding& robot) {
    ActuationSpec spec;
    for (const Drive& d : robot.drives) {
        GroupSpec g;
        for (const char* role : {"pitch", "yaw", "all"}) {
            try {
                if (select_joints(robot.spec, role) == d.joints) {
                    g.role = role;
                    break;
                }
            } catch (const SpecError&) {
                // the robot has no joints of this role
            }
        }
        if (g.role.empty()) g.joints = d.joints;
        g.controller = d.controller->ref();
        spec.groups.push_back(std::move(g));
    }
    return spec;
}

ActuationSpec relative_to(ActuationSpec spec, const std::string& file) {
    for (GroupSpec& g : spec.groups) {
        if (g.controller.kind == ControllerRef::Kind::file) {
            const std::string& from = g.controller.source;
            const std::string absolute =
                from.empty() ? g.controller.name : resolve_path(from, g.controller.name);
            g.controller.name = relative_path(absolute, file);
        }
    }
    return spec;
}

LoadedSimulation load_simulation(lua_State* L, const std::string& path) {
    LoadedSimulation out;
    // every file goes through input_path: noted for the run folders, a replay reads its copies
    out.file = read_simulation(checked_input_path(L, path));
    const EnvironmentSpec env =
        read_environment(checked_input_path(L, resolve_path(path, out.file.environment)));
    out.world = std::make_shared<WorldBinding>();
    out.world->spec = env.world;
    out.world->placements = env.placements;
    for (const RobotEntry& entry : out.file.robots) {
        auto robot = std::make_shared<RobotBinding>();
        robot->spec = read_robot(checked_input_path(L, resolve_path(path, entry.robot)));
        for (const auto& other : out.robots) {
            if (other->spec.name == robot->spec.name) {
                throw FormatError(fmt::format("{}:{}: two robots named '{}' (placements name "
                                              "robots: give each its own name)",
                                              path, entry.line, robot->spec.name),
                                  path, entry.line);
            }
        }
        std::vector<std::shared_ptr<Controller>> controllers;
        if (!entry.actuation.empty()) {
            controllers =
                actuate(L, *robot,
                        read_actuation(checked_input_path(L, resolve_path(path, entry.actuation))));
        }
        out.world->add(robot, std::nullopt);
        out.robots.push_back(robot);
        out.controllers.push_back(std::move(controllers));
    }
    for (const Placement& p : env.placements) {
        bool found = false;
        for (const auto& r : out.robots)
            found = found || r->spec.name == p.robot;
        if (!found) {
            const std::string env_file = resolve_path(path, out.file.environment);
            throw FormatError(fmt::format("{}:{}: robot '{}' is placed but the simulation has no "
                                          "robot of that name",
                                          env_file, p.line, p.robot),
                              env_file, p.line);
        }
    }
    return out;
}

EnvironmentSpec environment_of(const WorldBinding& world) {
    EnvironmentSpec env;
    env.world = world.spec;
    for (const WorldBinding::Entry& e : world.robots) {
        const std::string& name = e.robot->spec.name;
        for (const Placement& p : env.placements) {
            if (p.robot == name) {
                throw SpecError(fmt::format(
                    "two robots are named '{}': give each its own name to save where they are",
                    name));
            }
        }
        env.placements.push_back({name, e.pose});
    }
    // where robots of other names go (world:place, a loaded environment file) is kept too
    for (const Placement& p : world.placements) {
        bool placed = false;
        for (const Placement& q : env.placements)
            placed = placed || q.robot == p.robot;
        if (!placed) env.placements.push_back({p.robot, p.pose});
    }
    return env;
}

std::string normalized_config(const std::string& master, std::vector<ConfigFile>& parts) {
    SimulationFile file = read_simulation(master);
    const std::string stem = fs::path(master).stem().string();
    const std::string env_path = resolve_path(master, file.environment);
    file.environment = stem + ".environment.xml";
    parts.push_back({"environment", file.environment, env_path,
                     format_environment(read_environment(env_path)), "", 0, ""});
    std::set<std::string> taken;
    for (RobotEntry& entry : file.robots) {
        const std::string robot_path = resolve_path(master, entry.robot);
        const RobotSpec robot = read_robot(robot_path);
        const std::string part = file_name_part(robot.name, taken);
        entry.robot = stem + "." + part + ".robot.xml";
        parts.push_back({"robot", entry.robot, robot_path, format_robot(robot), "", 0, ""});
        if (entry.actuation.empty()) continue;
        const std::string act_path = resolve_path(master, entry.actuation);
        ActuationSpec act = read_actuation(act_path);
        for (GroupSpec& g : act.groups) {
            if (g.controller.kind == ControllerRef::Kind::file) {
                g.controller.name = resolve_path(act_path, g.controller.name);
            }
        }
        entry.actuation = stem + "." + part + ".actuation.xml";
        parts.push_back({"actuation", entry.actuation, act_path, format_actuation(act), "", 0, ""});
    }
    return format_simulation(file);
}

void save_simulation(const std::string& path, const WorldBinding& world,
                     const SimulationOptions& options, double duration,
                     const std::string& simulation_name, const RecordSpec& record) {
    const fs::path master(path);
    const std::string stem = master.stem().string();
    // the parts are named after the file: a name without a stem ("", ".", "dir/") would make
    // hidden files (".environment.xml") beside a folder
    if (stem.empty() || stem == "." || stem == ".." || master.filename().empty()) {
        throw WriteError(path,
                         "a file name expected, as in walk.xml (its parts are named "
                         "walk.environment.xml, walk.ROBOT.robot.xml ...)");
    }
    const auto next_to = [&](const std::string& name) {
        return (master.parent_path() / name).string();
    };
    SimulationFile file;
    file.name = simulation_name.empty() ? stem : simulation_name;
    file.options = options;
    file.duration = duration;
    file.record = record;
    file.environment = stem + ".environment.xml";
    // every part is built and checked, then every file written at once (write_files_atomic):
    // a save that fails leaves every file as it was
    std::vector<std::pair<std::string, std::string>> files;
    std::set<std::string> taken;
    for (const WorldBinding::Entry& e : world.robots) {
        // the robot's name names its files only once it cannot leave the folder
        const std::string name = file_name_part(e.robot->spec.name, taken);
        RobotEntry entry;
        entry.robot = stem + "." + name + ".robot.xml";
        files.emplace_back(next_to(entry.robot), format_robot(e.robot->spec));
        if (!e.robot->drives.empty()) {
            entry.actuation = stem + "." + name + ".actuation.xml";
            const std::string act_path = next_to(entry.actuation);
            files.emplace_back(act_path,
                               format_actuation(relative_to(actuation_of(*e.robot), act_path)));
        }
        file.robots.push_back(entry);
    }
    const std::string env_path = next_to(file.environment);
    files.emplace_back(
        env_path, checked_environment_text(format_environment(environment_of(world), env_path)));
    files.emplace_back(path, format_simulation(file));
    create_folders_above(path);
    // a folder that cannot be written to fails the save as a whole, not its first part
    const std::string folder =
        master.parent_path().empty() ? std::string(".") : master.parent_path().string();
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        throw WriteError(path, std::generic_category().message(errno));
    }
    try {
        write_files_atomic(files);
    } catch (const WriteError& e) {
        // a part that fails is named with the file asked for: the message says which save
        if (e.path() == path) throw;
        throw WriteError(path, e.reason(), e.folder(), e.path());
    }
}

}  // namespace gaitlab::scripting
