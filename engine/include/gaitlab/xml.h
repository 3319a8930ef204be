// Configuration files: robot, actuation, environment and simulation (the master that names the
// other three), each a versioned XML file (<gaitlab version="1">) described in docs/formats.md.
// Readers check everything before they return; writers check the spec before they write and
// write atomically, so a failed save leaves the old file as it was.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/actuation.h"
#include "gaitlab/error.h"
#include "gaitlab/options.h"
#include "gaitlab/robot.h"
#include "gaitlab/world.h"

namespace gaitlab {

/// Where a robot of the simulation lies in its environment.
struct Placement {
    std::string robot;  ///< the robot's name
    Pose pose;          ///< robot frame in the world frame
    int line = 0;       ///< its <place> element's line when read from a file (0: not read)
};

/// An environment file: everything of a world but its robots, and where the robots go.
struct EnvironmentSpec {
    WorldSpec world;  ///< its `robots` stay empty
    std::vector<Placement> placements;
};

/// One robot of a simulation file: the files of its body and of its actuation, as written
/// (relative paths are relative to the simulation file's folder).
struct RobotEntry {
    std::string robot;
    std::string actuation;  ///< "" for a robot without controllers
    int line = 0;           ///< its <robot> element's line when read from a file (0: not read)
};

/// What a run records (see docs/data.md); written in the simulation file.
struct RecordSpec {
    /// record or not; unset: as the host decides (`gaitlab run` records by default)
    std::optional<bool> enabled;
    std::string dir;           ///< run folder ("" = runs/<name>-<timestamp>/)
    int every = 0;             ///< ticks between samples (0 = every control tick)
    double flush_seconds = 2;  ///< wall time between flushes to disk, s
};

/// A simulation (master) file: options, the parts it is made of, how long it runs.
struct SimulationFile {
    std::string name = "simulation";
    SimulationOptions options = default_simulation_options();
    double duration = 10;     ///< simulated seconds `gaitlab run` runs it for
    std::string environment;  ///< the environment file, as written
    std::vector<RobotEntry> robots;
    RecordSpec record;
    int line = 0;  ///< the <simulation> element's line when read from a file (0: not read)
};

/// File readers: `path` is read and checked; `parse_*` read text (`file` names it in messages).
/// All throw FormatError (malformed input, unknown elements or attributes, values out of
/// range, an unreadable file).
RobotSpec read_robot(const std::string& path);
RobotSpec parse_robot(std::string_view text, const std::string& file);
ActuationSpec read_actuation(const std::string& path);
ActuationSpec parse_actuation(std::string_view text, const std::string& file);
/// A group's joints as an actuation file's <group joints="..."> gives them: a role ("pitch",
/// "yaw", "all") or joint numbers from 1, each once. Throws SpecError (without the attribute's
/// name, which the caller adds).
void parse_group_joints(const std::string& text, GroupSpec& group);
EnvironmentSpec read_environment(const std::string& path);
EnvironmentSpec parse_environment(std::string_view text, const std::string& file);
SimulationFile read_simulation(const std::string& path);
SimulationFile parse_simulation(std::string_view text, const std::string& file);

/// File writers: check the spec (SpecError), create the missing folders above `path` and write
/// it atomically (WriteError, an IoError naming `path`).
void write_robot(const std::string& path, const RobotSpec& robot);
std::string format_robot(const RobotSpec& robot);
void write_actuation(const std::string& path, const ActuationSpec& actuation);
std::string format_actuation(const ActuationSpec& actuation);
void write_environment(const std::string& path, const EnvironmentSpec& environment);
/// `text` (an environment file's) unchanged if gaitlab can read it back; SpecError when it is
/// larger than the reader's limit (kMaxInputBytes), saying how to make it smaller.
std::string checked_environment_text(std::string text);
/// `file`: where the text will be written (heightfield images are named relative to it; "":
/// as the spec holds them).
std::string format_environment(const EnvironmentSpec& environment, const std::string& file = "");
void write_simulation(const std::string& path, const SimulationFile& simulation);
std::string format_simulation(const SimulationFile& simulation);

/// `path` resolved against the folder of the file `from` (unless absolute).
std::string resolve_path(const std::string& from, const std::string& path);
/// `path` as a file written at `from_file` names it: relative to its folder when the two are in
/// the same folder tree (or one level apart), so they can move together; absolute otherwise.
std::string relative_path(const std::string& path, const std::string& from_file);

}  // namespace gaitlab
