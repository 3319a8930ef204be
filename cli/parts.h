// The parts of a simulation as `gaitlab new` (the wizard) and `gaitlab make` (expert mode)
// choose them, and the one place that turns those choices into files: robot, actuation,
// environment and simulation XML (docs/formats.md) and new Lua controller files. Both commands
// go through PartMaker, so a file the wizard writes is the file `gaitlab make` writes for the
// same choices, and every choice is checked by the engine itself (its messages, in its words).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gaitlab/error.h"

namespace gaitlab::scripting {
class LuaHost;
}

namespace gaitlab::cli {

/// A parameter name and the value chosen for it (in the parameter's unit).
using ParamValues = std::vector<std::pair<std::string, double>>;

/// A sensor to attach: `kind` (joint, imu, contact, range, position) and where (`at`: the
/// module, or the joint for `joint`; 0: the default place, see docs/console.md).
struct SensorChoice {
    std::string kind;
    int at = 0;
};

/// A chain robot.
struct RobotChoice {
    std::string name = "snake";
    int modules = 8;
    std::string connection = "pitch-pitch";  ///< pitch-pitch, pitch-yaw or yaw-yaw
    std::string module = "y1";               ///< a module type of the module library
    std::vector<SensorChoice> sensors;
};

/// The controller of a group: a built-in, a template or a Lua controller file, with parameter
/// values (parameters not listed keep their defaults).
struct ControllerChoice {
    /// stub: a Lua controller of that name that does nothing, standing in for a new
    /// controller whose file is not written yet (the wizard checks its groups with it)
    enum class Kind { builtin, template_, file, stub };
    Kind kind = Kind::builtin;
    std::string name = "sine";  ///< built-in or template name, or the file's path
    ParamValues params;
};

/// A joint group and the controller that drives it.
struct GroupChoice {
    std::string joints = "pitch";  ///< "pitch", "yaw", "all", or joint numbers "1 3 5"
    ControllerChoice controller;
};

/// A world of the world library (gaitlab.worlds) with its parameters.
struct WorldChoice {
    std::string preset = "flat";
    ParamValues params;  ///< friction among them
    /// the robot the preset's start placement is for ("": none, unless the preset's start is
    /// not the origin, then "robot")
    std::string place;
};

/// The options of a simulation file.
struct SimChoice {
    std::string name = "simulation";
    double duration = 10;    ///< s
    double dt = 0.001;       ///< s
    int control_every = 30;  ///< physics steps between controller steps
    int solver_iterations = 20;
    bool record = true;
};

/// One parameter of a new Lua controller.
struct NewParam {
    std::string name;
    double value = 0;  ///< initial value
    double min = 0, max = 0;
    std::string unit;
};

/// A new Lua controller: its name, parameters and per-joint values.
struct NewController {
    std::string name = "my_controller";
    std::vector<NewParam> params;
    std::vector<std::string> values;
};

/// A parameter as a controller or world preset declares it.
struct ParamInfo {
    std::string name;
    double value = 0;  ///< default
    double min = 0, max = 0;
    std::string unit;
};

/// A world of the world library.
struct PresetInfo {
    std::string name;
    std::string description;
    std::vector<ParamInfo> params;  ///< sorted by name
};

/// A joint of a robot file: its number from 1 and its role.
struct JointInfo {
    int index = 0;
    std::string role;
};

/// Builds, checks and writes the parts, through a Lua host of its own (the engine's builders
/// and writers: gaitlab.robot.chain, robot:save, gaitlab.worlds, world:save, ...) that records
/// nothing. Every failure is a gaitlab::Error whose message is the engine's, without Lua's
/// "bad argument #1 to 'chain' (...)" wrapping.
class PartMaker {
  public:
    PartMaker();
    ~PartMaker();
    PartMaker(const PartMaker&) = delete;
    PartMaker& operator=(const PartMaker&) = delete;

    /// Names of the built-in controllers, of the templates and of the worlds, sorted.
    std::vector<std::string> builtins();
    std::vector<std::string> templates();
    std::vector<PresetInfo> presets();
    /// The parameters of a built-in controller or a template (sorted by name).
    std::vector<ParamInfo> controller_params(const ControllerChoice& c);

    /// Throws Error unless the robot can be built (name, modules, connection, module, sensors).
    void check_robot(const RobotChoice& robot);
    /// The joints of the robot, from the tail.
    std::vector<JointInfo> joints(const RobotChoice& robot);
    /// Throws Error unless the controller can be made with these parameter values.
    void check_controller(const ControllerChoice& c);
    /// Throws Error unless `groups` can drive `robot` (joints exist, each group's controller
    /// can be made, no controller drives a joint twice... as robot:group():drive() says).
    void check_groups(const RobotChoice& robot, const std::vector<GroupChoice>& groups);
    /// Throws Error unless the new controller's declaration is valid.
    void check_new_controller(const NewController& c);
    /// Throws Error unless the world can be built.
    void check_world(const WorldChoice& world);
    /// Throws Error unless the options are valid (dt, control_every, duration).
    static void check_sim(const SimChoice& sim);

    /// Writes a robot file.
    void write_robot(const RobotChoice& robot, const std::string& path);
    /// The name of the robot a robot file holds.
    std::string robot_name(const std::string& robot_file);
    /// Writes the actuation file of the robot in `robot_file` driven by `groups` (Lua controller
    /// files are named relative to `path`).
    void write_actuation(const std::string& robot_file, const std::vector<GroupChoice>& groups,
                         const std::string& path);
    /// Writes an environment file.
    void write_world(const WorldChoice& world, const std::string& path);
    /// Writes a simulation file naming the three files (relative to `path`'s folder when they
    /// are in its folder tree), after loading all of it to check that it runs: written only if
    /// it loads. `actuation_file` may be "".
    void write_sim(const SimChoice& sim, const std::string& robot_file,
                   const std::string& actuation_file, const std::string& world_file,
                   const std::string& path);
    /// Writes a new Lua controller file whose step() moves the joints as written (a sine
    /// wave) and says where to write the gait; checks that the file loads.
    void write_new_controller(const NewController& c, const std::string& path);
    /// Copies a template into a new controller file.
    void write_template(const std::string& name, const std::string& path);

  private:
    // runs `code` (a chunk of this file's helpers) and returns with `nresults` results on the
    // stack; throws Error with the engine's message
    void eval(const std::string& code, int nresults);
    std::unique_ptr<scripting::LuaHost> host_;
};

/// `text` as a Lua string literal: every byte that is not a letter, digit, space or one of
/// `_-.,:/+=` escaped, so no text can end the literal.
std::string lua_quote(const std::string& text);

/// A number as gaitlab writes it: the shortest text that reads back to the same value.
std::string number_text(double v);

/// Parses a finite number ("40", "-1.5e3"); false if `text` is not one.
bool parse_number(const std::string& text, double& out);

/// Parses joints as a group takes them: "pitch", "yaw", "all", or numbers from 1 separated by
/// spaces or commas ("1 3 5", "1,3,5"); returns "" and sets `error` when it is neither.
std::string parse_joints(const std::string& text, std::string& error);

/// Parses "NAME=VALUE" pairs separated by spaces, commas or colons; throws Error naming the
/// bad pair.
ParamValues parse_params(const std::string& text);

/// Parses a sensor as `gaitlab make robot --sensor` takes it: KIND or KIND:N (N the module,
/// or the joint for `joint`); throws Error.
SensorChoice parse_sensor(const std::string& text);

/// Parses a controller: NAME (built-in), template/NAME, or PATH.lua (a Lua controller file).
ControllerChoice parse_controller(const std::string& text);

/// Parses a group as `gaitlab make actuation --group` takes it:
/// JOINTS=CONTROLLER[:PARAM=VALUE...]; throws Error.
GroupChoice parse_group(const std::string& text);

}  // namespace gaitlab::cli
