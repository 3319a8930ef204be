#include "scene.h"

#include "gaitlab/error.h"

namespace gaitlab::scripting {

std::shared_ptr<Simulation> RobotBinding::live() const {
    auto s = sim.lock();
    if (!s && in_world && index >= 0) {
        // it was in one: the newest simulation of its world, collected since
        throw Error("robot '" + spec.name +
                    "' is in no simulation now: the newest simulation built from its world is "
                    "gone (nothing held it); create another: gaitlab.simulation{world = ...}");
    }
    if (!s && in_world) {
        throw Error("robot '" + spec.name +
                    "' is not in a simulation yet (its world is built into one by "
                    "gaitlab.simulation{world = ...})");
    }
    if (!s) {
        throw Error("robot '" + spec.name +
                    "' is not in a simulation (add it to a world, then create "
                    "gaitlab.simulation{world = ...})");
    }
    return s;
}

void RobotBinding::drive(std::vector<int> joints, std::shared_ptr<Controller> controller,
                         Origin origin) {
    Drive d{std::move(joints), std::move(controller)};
    check_new_group(drives, d, spec.name);
    if (auto s = sim.lock()) s->add_drive(index, d, origin);
    drives.push_back(std::move(d));
}

void WorldBinding::add(std::shared_ptr<RobotBinding> robot, std::optional<Pose> pose) {
    if (robot->in_world) throw Error("robot '" + robot->spec.name + "' is already in a world");
    if (!pose) {
        pose = Pose{};
        for (const Placement& p : placements) {
            if (p.robot == robot->spec.name) pose = p.pose;
        }
    }
    robots.push_back({robot, *pose});
    robot->in_world = true;
}

int RobotBinding::attach(SensorSpec sensor) {
    if (auto s = sim.lock()) s->add_sensor(index, sensor);
    spec.sensors.push_back(std::move(sensor));
    return static_cast<int>(spec.sensors.size()) - 1;
}

void RobotBinding::set_sensor_enabled(int k, bool on, Origin origin) {
    if (auto s = sim.lock()) s->set_sensor_enabled(s->sensor_index(index, k), on, origin);
    spec.sensors[static_cast<size_t>(k)].enabled = on;
}

std::shared_ptr<Simulation> WorldBinding::compile(const SimulationOptions& options) const {
    WorldSpec world = spec;
    for (const Entry& e : robots)
        world.robots.push_back({e.robot->spec, e.pose, e.robot->drives});
    return std::make_shared<Simulation>(std::move(world), options);
}

void WorldBinding::link(const std::shared_ptr<Simulation>& sim) const {
    // every robot handle of the world becomes the new simulation's robot, its controllers
    // included: the ones its groups are driven by there (the handle's own for a first
    // simulation, fresh copies of them for a later one). An older simulation keeps its own
    for (size_t r = 0; r < robots.size(); ++r) {
        RobotBinding& robot = *robots[r].robot;
        robot.sim = sim;
        robot.index = static_cast<int>(r);
        robot.drives = sim->world().robots[r].actuation;
    }
}

bool drives_of(const RobotBinding& robot, const Simulation& sim, int index) {
    const Actuation& there = sim.world().robots[static_cast<size_t>(index)].actuation;
    if (robot.drives.size() != there.size()) return false;
    for (size_t d = 0; d < there.size(); ++d) {
        if (robot.drives[d].controller != there[d].controller) return false;
    }
    return true;
}

std::shared_ptr<RobotBinding> robot_of(const std::shared_ptr<Simulation>& sim, int index) {
    auto robot = std::make_shared<RobotBinding>();
    const PlacedRobot& placed = sim->world().robots[static_cast<size_t>(index)];
    robot->spec = placed.robot;
    robot->drives = placed.actuation;
    robot->in_world = true;
    robot->sim = sim;
    robot->index = index;
    return robot;
}

std::shared_ptr<WorldBinding> WorldBinding::of(const std::shared_ptr<Simulation>& sim,
                                               const WorldBinding& like) {
    auto world = std::make_shared<WorldBinding>();
    world->spec = sim->world();
    world->spec.robots.clear();
    world->placements = like.placements;
    for (int r = 0; r < sim->robot_count(); ++r) {
        world->robots.push_back(
            {robot_of(sim, r), sim->world().robots[static_cast<size_t>(r)].pose});
    }
    return world;
}

}  // namespace gaitlab::scripting
