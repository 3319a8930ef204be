// Configuration files on the Lua side: building live controllers from the references of an
// actuation file (built-ins, Lua controller files, templates), the references of a robot's live
// controllers, and whole simulations to and from a simulation file with its parts.
#pragma once

#include <lua.hpp>

#include <memory>
#include <string>
#include <vector>

#include "gaitlab/recorder.h"
#include "gaitlab/xml.h"
#include "scene.h"

namespace gaitlab::scripting {

/// The file a script's `arg` names as input_path gives it (relative to the calling script, or
/// the replay's copy of it), once check_file says it can be read: a directory, a device, a
/// FIFO or a huge file is refused before anything opens it. Throws FormatError "PATH: cannot
/// read the file: REASON", as the XML readers do.
std::string checked_input_path(lua_State* L, const std::string& arg);

/// The controller `ref` names, with its parameters set. Lua controller files (relative to the
/// file the reference was read from) load through the controller-file cache, so they hot
/// reload. Errors (an unknown controller or parameter, a value out of range, a broken Lua
/// file) are FormatError at the reference's file and line, or ScriptError from Lua.
std::shared_ptr<Controller> make_controller(lua_State* L, const ControllerRef& ref);

/// Drives `robot` as `spec` says; returns the controllers, one per group. Checks every group
/// and builds every controller before driving any, so a bad file changes nothing.
std::vector<std::shared_ptr<Controller>> actuate(lua_State* L, RobotBinding& robot,
                                                 const ActuationSpec& spec);

/// The actuation of a robot's drives: each group by role when a role selects exactly its
/// joints, the controllers by ref() (SpecError for controllers defined inside a script).
ActuationSpec actuation_of(const RobotBinding& robot);

/// Lua controller files of `spec` named relative to the folder of `file` (as an actuation file
/// written at `file` should name them).
ActuationSpec relative_to(ActuationSpec spec, const std::string& file);

/// A world that a simulation file describes, with its robots placed and driven.
struct LoadedSimulation {
    SimulationFile file;
    std::shared_ptr<WorldBinding> world;
    std::vector<std::shared_ptr<RobotBinding>> robots;
    std::vector<std::vector<std::shared_ptr<Controller>>> controllers;  ///< per robot
};

/// Reads the simulation file at `path` and everything it names. Throws FormatError,
/// ScriptError or SpecError; builds nothing half-way.
LoadedSimulation load_simulation(lua_State* L, const std::string& path);

/// The environment file of a world: its objects and where each of its robots is (robots are
/// placed by name, so two robots with one name are a SpecError).
EnvironmentSpec environment_of(const WorldBinding& world);

/// The configuration a run folder keeps of the simulation file `master`, normalized so it stands
/// on its own: the master's text, naming its parts as `<stem>.environment.xml`,
/// `<stem>.<robot>.robot.xml` and `<stem>.<robot>.actuation.xml` next to it (names made safe
/// as save_simulation makes them), and those parts
/// (roles "environment", "robot", "actuation"). Lua controller files are named by absolute path
/// (the run folder keeps their code itself). Throws FormatError.
std::string normalized_config(const std::string& master, std::vector<ConfigFile>& parts);

/// Writes a simulation file at `path` and its parts next to it: `<stem>.environment.xml`, and
/// for each robot `<stem>.<robot>.robot.xml` and `<stem>.<robot>.actuation.xml`, where
/// `<robot>` is the robot's name made safe as part of a file name (ASCII letters, digits, '-',
/// '_' and non-ASCII kept, anything else '_', at most 64 bytes, unique): no name writes outside
/// the folder of `path`. Checks everything (unique robot names, nameable controllers)
/// before writing anything. Creates the folder of `path` if missing (as `mkdir -p`); a failure
/// is a WriteError naming `path` (and the part, if a part failed).
/// `simulation_name` ("" : the stem of `path`) and `record` are written as the simulation's name
/// and <record>.
void save_simulation(const std::string& path, const WorldBinding& world,
                     const SimulationOptions& options, double duration,
                     const std::string& simulation_name = "", const RecordSpec& record = {});

}  // namespace gaitlab::scripting
