// What Lua handles hold: a robot or world under construction, and the link from a robot to the
// simulation it was compiled into.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gaitlab/controller.h"
#include "gaitlab/simulation.h"
#include "gaitlab/world.h"
#include "gaitlab/xml.h"

namespace gaitlab::scripting {

/// A robot as Lua sees it: its spec, its drives, and where it runs.
struct RobotBinding {
    RobotSpec spec;
    /// its groups and controllers; once in a simulation, the ones that simulation drives
    Actuation drives;
    bool in_world = false;
    /// the simulation it is the robot of: for a world's handle the newest its world built
    std::weak_ptr<Simulation> sim;
    int index = -1;  ///< its robot index in that simulation

    /// The running simulation; throws Error if the robot is not in one.
    std::shared_ptr<Simulation> live() const;
    /// Drives `joints` with `controller`, now and in the running simulation if any.
    void drive(std::vector<int> joints, std::shared_ptr<Controller> controller,
               Origin origin = Origin::script);
    /// Attaches a sensor (validated), now and in the running simulation if any; returns its
    /// index among the robot's sensors.
    int attach(SensorSpec sensor);
    /// Switches the robot's sensor k on or off, in the spec and in the running simulation
    /// (where `origin` stamps the event).
    void set_sensor_enabled(int k, bool on, Origin origin = Origin::script);
};

/// Whether `robot`'s drives are the controllers robot `index` of `sim` is driven by.
bool drives_of(const RobotBinding& robot, const Simulation& sim, int index);

/// A robot handle for robot `index` of `sim` (its spec and drives as they are there).
std::shared_ptr<RobotBinding> robot_of(const std::shared_ptr<Simulation>& sim, int index);

/// A world as Lua sees it: its spec without robots, and the robots added to it.
struct WorldBinding {
    WorldSpec spec;
    struct Entry {
        std::shared_ptr<RobotBinding> robot;
        Pose pose;
    };
    std::vector<Entry> robots;
    /// Where robots go by name when added without a pose (from an environment file).
    std::vector<Placement> placements;

    /// Adds a robot at `pose`, or without one where `placements` puts a robot of its name, or
    /// else with its tail at the origin; throws Error if the robot is in a world already.
    void add(std::shared_ptr<RobotBinding> robot, std::optional<Pose> pose);
    /// Compiles the world into a simulation, driven by the handles' controllers where no
    /// living simulation drives them (a first simulation, or the previous one is gone), else
    /// by fresh copies of them as they stand (the previous simulation's, parameters as they
    /// are then: Simulation's constructor). The handles are not changed: link() does that once
    /// the simulation is made for good, so a build that fails changes no handle.
    std::shared_ptr<Simulation> compile(const SimulationOptions& options) const;
    /// Makes every robot handle of the world `sim`'s robot (compiled from this world): its
    /// state, its sensors and its drives (the controllers the simulation's groups are driven
    /// by). An older simulation keeps its controllers; sim:robot gives its robots handles of
    /// their own (robot_of).
    void link(const std::shared_ptr<Simulation>& sim) const;
    /// The world of a simulation made without one (a clone): its robots linked to `sim`.
    static std::shared_ptr<WorldBinding> of(const std::shared_ptr<Simulation>& sim,
                                            const WorldBinding& like);
};

/// A controller handle: the instance, and whether a group already uses it.
struct ControllerHandle {
    std::shared_ptr<Controller> controller;
    bool attached = false;
};

/// A joint group of a robot (0-based joint indices).
struct GroupHandle {
    std::shared_ptr<RobotBinding> robot;
    std::vector<int> joints;
};

}  // namespace gaitlab::scripting
