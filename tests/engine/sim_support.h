// Helpers shared by the engine tests that run a simulation: chain worlds, sine drives and a
// recorded run.
#pragma once

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "gaitlab/controller.h"
#include "gaitlab/controllers/sine.h"
#include "gaitlab/recorder.h"
#include "gaitlab/robot.h"
#include "gaitlab/simulation.h"
#include "gaitlab/world.h"

namespace gaitlab::test {

/// A world holding `robot` on a floor of friction 0.8.
inline WorldSpec world_of(RobotSpec robot) {
    WorldSpec world;
    world.floor.friction = 0.8;
    PlacedRobot placed;
    placed.robot = std::move(robot);
    world.robots.push_back(std::move(placed));
    return world;
}

/// A world holding one chain of `modules` modules lying on the floor (or floating, with
/// `gravity` false: no gravity and no floor).
inline WorldSpec chain_world(int modules, Connection connection, bool gravity = true) {
    ChainSpec chain;
    chain.name = "snake";
    chain.modules = modules;
    chain.connection = connection;
    WorldSpec world = world_of(make_chain(chain));
    if (!gravity) {
        world.gravity = {0, 0, 0};
        world.floor.enabled = false;
    }
    return world;
}

/// The options of the convergence measurements: time step `dt` with the control period kept at
/// 10 ms, `iterations` solver iterations, `solver`.
inline SimulationOptions options_at(double dt, int iterations = 20,
                                    ConstraintSolver solver = ConstraintSolver::pgs) {
    SimulationOptions o;
    o.dt = dt;
    o.control_every = static_cast<int>(std::lround(0.01 / dt));
    o.solver_iterations = iterations;
    o.solver = solver;
    return o;
}

/// A sine generator with the given parameters (degrees, Hz).
inline std::shared_ptr<controllers::Sine> sine(double amplitude, double frequency, double phase,
                                               double phase0 = 0, double offset = 0) {
    auto s = std::make_shared<controllers::Sine>();
    s->set_param("amplitude", amplitude);
    s->set_param("frequency", frequency);
    s->set_param("phase", phase);
    s->set_param("phase0", phase0);
    s->set_param("offset", offset);
    return s;
}

/// Drives the joints of robot 0 with role `role` ("pitch", "yaw", "all") by `controller`.
inline void drive(Simulation& sim, std::string_view role, std::shared_ptr<Controller> controller) {
    Drive d;
    d.joints = select_joints(sim.world().robots[0].robot, role);
    d.controller = std::move(controller);
    sim.add_drive(0, std::move(d));
}

/// The classic pitch-pitch caterpillar gait of first_snake.lua (A 40 deg, f 0.5 Hz).
inline void drive_pitch_pitch_gait(Simulation& sim, double phase) {
    drive(sim, "pitch", sine(40, 0.5, phase));
}

/// A pitch-yaw gait: the pitch joints make a travelling wave, the yaw joints the same wave a
/// quarter period later (a side-winding/rolling pattern).
inline void drive_pitch_yaw_gait(Simulation& sim) {
    drive(sim, "pitch", sine(40, 0.5, 120));
    drive(sim, "yaw", sine(30, 0.5, 120, 90));
}

/// A sine wave on every joint of its group that throws "faulty broke" once the simulation
/// time reaches `fail_at`; `steps` counts the steps it made. Copied with its state.
class Faulty final : public Controller {
  public:
    explicit Faulty(double fail_at)
        : Controller(ControllerDef{"faulty", {}, {}}), fail_at_(fail_at) {}
    void step(ControlIO& io) override {
        if (io.time() >= fail_at_) throw std::runtime_error("faulty broke");
        ++steps;
        for (int m = 0; m < io.joints(); ++m)
            io.set_target(m, 0.6 * std::sin(6.0 * io.time() + m));
    }
    std::unique_ptr<Controller> clone() const override {
        return std::unique_ptr<Controller>(new Faulty(*this));
    }
    int steps = 0;

  private:
    double fail_at_;
};

/// Records `seconds` of a 4-module snake crawling with a sine on its pitch joints into the run
/// folder `dir`, closed as finished; returns `dir`.
inline std::string record_run(const std::string& dir, double seconds) {
    Simulation sim(chain_world(4, Connection::pitch_pitch));
    drive(sim, "pitch", sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = dir;
    Recorder rec(sim, o);
    sim.run(seconds);
    rec.close();
    return dir;
}

/// `n` bodies of `size` (m) and `mass` (kg) in a row along x on the floor, centred on the
/// origin, joined by hinges about `axis` (pitch: +y, yaw: +z; ranges of +-60 deg) whose servos
/// give at most `torque` (N m): the long thin and long heavy chains of the solver's limits.
inline RobotSpec slender_chain(int n, const Vec3& size, double mass, const Vec3& axis,
                               double torque) {
    RobotSpec r;
    r.name = "slender";
    for (int k = 0; k < n; ++k) {
        BodySpec b;
        b.name = "b" + std::to_string(k);
        b.size = size;
        b.mass = mass;
        b.pose.position = {size.x * (k + 0.5 - n / 2.0), 0, size.z / 2};
        r.bodies.push_back(b);
    }
    for (int k = 1; k < n; ++k) {
        JointSpec j;
        j.name = "j" + std::to_string(k);
        j.role = axis.z != 0 ? JointRole::yaw : JointRole::pitch;
        j.parent = k - 1;
        j.child = k;
        j.pivot = {size.x * (k - n / 2.0), 0, size.z / 2};
        j.axis = axis;
        j.min_angle = -deg_to_rad(60);
        j.max_angle = deg_to_rad(60);
        j.servo.max_torque = torque;
        r.joints.push_back(j);
    }
    return r;
}

/// A branch: a body of `size` hung beside body `at` of `robot` (its centre `offset` m along +y
/// from that body's) on a hinge about x whose pivot is `pivot` m along +y from the body's
/// centre, modelled on the robot's first joint (its servo). Body `at` then has three hinges.
inline void add_branch(RobotSpec& robot, int at, const Vec3& size, double offset, double pivot) {
    BodySpec side = robot.bodies[static_cast<size_t>(at)];
    side.name = "side";
    side.size = size;
    side.pose.position.y += offset;
    robot.bodies.push_back(side);
    JointSpec j = robot.joints[0];
    j.name = "js";
    j.role = JointRole::pitch;
    j.parent = at;
    j.child = static_cast<int>(robot.bodies.size()) - 1;
    j.pivot = robot.bodies[static_cast<size_t>(at)].pose.position;
    j.pivot.y += pivot;
    j.axis = {1, 0, 0};
    robot.joints.push_back(j);
}

}  // namespace gaitlab::test
