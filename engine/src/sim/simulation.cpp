#include "gaitlab/simulation.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <set>
#include <string_view>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bullet/physics_world.h"
#include "gaitlab/checked.h"
#include "gaitlab/controller.h"
#include "gaitlab/error.h"
#include "gaitlab/servo.h"
#include "sim/sensing.h"
#include "spec/check.h"

namespace gaitlab {

Scheduler::Scheduler(double dt, int control_every)
    : dt_(dt), control_every_(control_every), control_dt_(dt * control_every) {}

namespace {

// what a simulation may be busy running (Simulation::busy_)
constexpr const char* kController = "a controller's step";
constexpr const char* kObserver = "an observer";
constexpr const char* kPreTick = "a pre-tick hook";
constexpr const char* kListener = "an event listener";

// beyond these a body has left any scene gaitlab simulates: the step diverged
constexpr double kMaxDistance = 1e5;  // m from the origin
constexpr double kMaxSpeed = 1e4;     // m/s

// a robot that starts deeper than this inside something gets a warning: the contact solver
// resolves deep overlaps with large impulses (a robot inside a box flies metres away). Deeper
// than the 1 mm margin convex hulls (ramps) add to a surface a robot rests on.
constexpr double kMaxStartOverlap = 0.005;  // m

// a robot whose bodies do not collide with each other (self_collision off) gets a warning
// when one of them enters another deeper than this (a long chain's coil passing through
// itself), checked every kSelfPassPeriod of simulated time: quick enough to see a 60 mm
// module entering another at 0.5 m/s before it is through
constexpr double kMaxSelfPass = 0.005;    // m
constexpr double kSelfPassPeriod = 0.01;  // s

// kSelfPassPeriod in steps of dt
long self_pass_ticks(double dt) {
    return std::max(1L, std::lround(kSelfPassPeriod / dt));
}

// a body whose weight would sink it by more than this part of its height into the compliant
// floor, resting on its lowest corners, gets a warning: the floor's springs (per contact point)
// suit robots of grams to kilograms, and a heavier body sinks and swings on them
constexpr double kMaxFloorSink = 0.1;

// the settings beyond which even the pitch-pitch travelling wave (8 modules, 40 deg, 0.5 Hz),
// which the defaults keep within 1.7 % of a converged reference (dt 0.25 ms, 80 iterations),
// moves by more than 3 % from it on a floor of friction 0.3. The default solver (pgs): 10
// iterations 3.7 % (15: 2.4 %), dt 2 ms 3.5 % (1.5 ms: 2.6 %); on a floor of 1.0 it stays within
// 3 % to dt 5 ms and 5 iterations. block_nncg (its own reference): 5 iterations at dt 10 ms 3.8 %
// (7: 1.5 %), 3 at 5 ms 3.9 %; every dt to 10 ms within 1.5 % from 7 iterations.
// docs/performance.md, "Convergence" and "Motors in the block"
struct AccuracyLimits {
    int min_iterations;
    double max_dt;  // s
};
AccuracyLimits accuracy_limits(ConstraintSolver solver) {
    if (solver == ConstraintSolver::block_nncg) return {7, 0.01};
    return {15, 0.0015};
}

// the robot with the most joints among those with pitch and yaw joints both, if it has more
// than kLongChainJoints: its index, else -1
int longest_bent_chain(const WorldSpec& world) {
    int found = -1;
    size_t most = kLongChainJoints;
    for (size_t r = 0; r < world.robots.size(); ++r) {
        const std::vector<JointSpec>& joints = world.robots[r].robot.joints;
        const auto has = [&](JointRole role) {
            return std::any_of(joints.begin(), joints.end(),
                               [&](const JointSpec& j) { return j.role == role; });
        };
        if (has(JointRole::pitch) && has(JointRole::yaw) && joints.size() > most) {
            most = joints.size();
            found = static_cast<int>(r);
        }
    }
    return found;
}

// the warnings of dt, solver_iterations or solver that cannot keep a gait's speed within 3 %
// of a converged reference (docs/performance.md, "Convergence"), if the world has joints: one
// per setting
std::vector<std::string> accuracy_warnings(const WorldSpec& world,
                                           const SimulationOptions& options) {
    std::vector<std::string> warnings;
    bool joints = false;
    for (const PlacedRobot& r : world.robots)
        joints = joints || !r.robot.joints.empty();
    if (!joints) return warnings;  // rigid bodies alone: nothing measured
    const AccuracyLimits limits = accuracy_limits(options.solver);
    const bool block = options.solver == ConstraintSolver::block_nncg;
    const auto warn = [&](const std::string& setting) {
        warnings.push_back(fmt::format(
            "{}: gaits then move more than 3 % faster or slower than with a converged solver "
            "(dt <= {:g} ms and solver_iterations >= {} keep a pitch-pitch travelling wave "
            "within 3 %{}; docs/performance.md, \"Convergence\")",
            setting, limits.max_dt * 1000, limits.min_iterations,
            block ? " with solver = \"block_nncg\"" : ""));
    };
    const int chain = longest_bent_chain(world);
    const std::string chain_is =
        chain < 0 ? ""
                  : fmt::format("robot '{}' has {} joints bending it in two planes (pitch and yaw)",
                                world.robots[static_cast<size_t>(chain)].robot.name,
                                world.robots[static_cast<size_t>(chain)].robot.joints.size());
    if (chain >= 0 && !block) {
        warnings.push_back(fmt::format(
            "solver = \"pgs\": {}, and pgs does not converge on such chains (on a floor of 1e5 "
            "N/m the 32-module rolling chain moved 77.0, 70.5 and 66.9 mm per cycle at 20, 80 "
            "and 320 iterations, where block_nncg converged to 83.2); take solver = "
            "\"block_nncg\", which gives such a robot newton_steps = {} when they are not "
            "given, or dt <= {:g} ms with solver_iterations >= {} (docs/performance.md, \"Long "
            "chains bent in two planes\" and \"Upright or on its side\")",
            chain_is, kLongChainNewtonSteps, kLongChainMaxDt * 1000, kLongChainIterations));
    }
    if (chain >= 0 && block) {
        // stricter than the general limits: one warning for both settings. newton_steps >=
        // kLongChainNewtonSteps converge the iterations' part, and on a floor as stiff as the
        // default or softer dt <= kLongChainNewtonMaxDt (1 ms) stays within 2 % of dt / 4
        // (docs/performance.md, "Upright or on its side"); without them, or on a stiffer floor
        // (whose contact dt 1 ms does not resolve: "A floor dt 1 ms resolves"), dt <=
        // kLongChainMaxDt
        const FloorSpec& floor = world.floor;
        const bool stiff_floor =
            floor.enabled && (floor.rigid || floor.stiffness.value_or(kDefaultFloorStiffness) >
                                                 kDefaultFloorStiffness * (1 + 1e-9));
        const bool newton = options.newton_steps >= kLongChainNewtonSteps;
        const double max_dt = newton && !stiff_floor ? kLongChainNewtonMaxDt : kLongChainMaxDt;
        std::vector<std::string> coarse;
        if (options.dt > max_dt * (1 + 1e-9)) {
            std::string why;
            if (newton && stiff_floor) {
                why = fmt::format(" on a floor stiffer than the default {:g} N/m",
                                  kDefaultFloorStiffness);
            } else if (newton) {
                why = fmt::format(" with newton_steps = {}", options.newton_steps);
            }
            coarse.push_back(fmt::format("dt = {:g} ms is above {:g} ms{}", options.dt * 1000,
                                         max_dt * 1000, why));
        }
        if (options.solver_iterations < kLongChainIterations && !newton) {
            coarse.push_back(fmt::format("solver_iterations = {} {}below {}{}",
                                         options.solver_iterations, coarse.empty() ? "is " : "",
                                         kLongChainIterations,
                                         fmt::format(" with newton_steps = {} below {}",
                                                     options.newton_steps, kLongChainNewtonSteps)));
        }
        if (!coarse.empty()) {
            warnings.push_back(fmt::format(
                "{}: {}, whose gaits settle into one of several motions (a wave upright or "
                "lying twisted on its side), which these settings move up to 7 % faster or "
                "slower than a converged solver, and they can change which one a start takes; "
                "newton_steps >= {} (what such a robot gets when newton_steps is not given) with "
                "dt <= {:g} ms keep each motion within 2 % on a floor as stiff as the default or "
                "softer, and dt <= {:g} ms with solver_iterations >= {} within 3 %; "
                "sim:check_accuracy() or gaitlab check measures this robot's gait "
                "(docs/performance.md, \"Upright or on its side\")",
                fmt::join(coarse, " and "), chain_is, kLongChainNewtonSteps,
                kLongChainNewtonMaxDt * 1000, kLongChainMaxDt * 1000, kLongChainIterations));
        }
        return warnings;
    }
    if (options.solver_iterations < limits.min_iterations) {
        warn(fmt::format("solver_iterations = {} is below {}", options.solver_iterations,
                         limits.min_iterations));
    }
    if (options.dt > limits.max_dt * (1 + 1e-9))
        warn(fmt::format("dt = {:g} ms is above {:g} ms", options.dt * 1000, limits.max_dt * 1000));
    return warnings;
}

}  // namespace

int automatic_newton_steps(const WorldSpec& world, ConstraintSolver solver) {
    return solver == ConstraintSolver::block_nncg && longest_bent_chain(world) >= 0
               ? kLongChainNewtonSteps
               : 0;
}

// marks the simulation busy running `what` for the lifetime of the guard (nested guards give
// back the outer mark)
class Simulation::Busy {
  public:
    Busy(Simulation& sim, const char* what) : sim_(sim), outer_(sim.busy_) { sim.busy_ = what; }
    ~Busy() { sim_.busy_ = outer_; }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

  private:
    Simulation& sim_;
    const char* outer_;
};

// the tick phases of a simulation (see scheduler.h for their order)
class Simulation::Phases final : public TickPhases, public JointReader {
  public:
    explicit Phases(Simulation& sim) : sim_(sim) {}

    void sense() override { sim_.physics_->read_angles(sim_.angles_.data()); }

    void think(double time, double control_dt) override {
        std::fill(sim_.targets_.begin(), sim_.targets_.end(), 0.0);
        // the drives there were when the tick began: one that a controller adds now acts from
        // the next control tick
        const Busy busy(sim_, kController);
        for (size_t i = 0, n = sim_.drives_.size(); i < n; ++i) {
            DriveSlot& d = sim_.drives_[i];
            Controller& c = *d.drive.controller;
            if (!c.failed()) {  // a failed controller's targets stay frozen
                ControlIO io(control_dt, time, d.global_joints, *this, d.targets.data(),
                             &sim_.sensing_->reader(d.robot));
                try {
                    c.step(io);
                } catch (const std::exception& e) {
                    sim_.fail(d, e);
                    if (sim_.options_.on_controller_error == ControllerErrorPolicy::stop) throw;
                }
            }
            for (size_t m = 0; m < d.global_joints.size(); ++m) {
                sim_.targets_[static_cast<size_t>(d.global_joints[m])] += d.targets[m];
            }
        }
        // overlapping groups add up; the sum stays inside the joint's range
        for (size_t j = 0; j < sim_.targets_.size(); ++j) {
            sim_.targets_[j] = std::clamp(sim_.targets_[j], min_[j], max_[j]);
        }
    }

    void act() override {
        for (size_t j = 0; j < servos_.size(); ++j) {
            sim_.commands_[j] = servo_command(servos_[j], sim_.targets_[j], sim_.angles_[j]);
        }
        sim_.physics_->set_motor_velocities(sim_.commands_.data());
    }

    void physics(double dt) override {
        sim_.physics_->step(dt);
        // every step, before the record phase: no observer (a recorder) ever sees the state
        // of a diverged step
        const int bad = sim_.physics_->first_diverged(kMaxDistance, kMaxSpeed);
        if (bad >= 0) sim_.diverged(bad, sim_.scheduler_.time() + dt);
    }

    void record(long tick, double time) override {
        if (sim_.self_pass_every_ > 0 && tick % sim_.self_pass_every_ == 0)
            sim_.check_self_pass(time);
        // the sensors read the state the step reached: the next tick's think sees it, and so
        // do the observers
        sim_.sensing_->update(*sim_.physics_);
        sim_.track_headings(false);
        sim_.integrate_energy();
        if (sim_.observers_.idle()) return;
        const Busy busy(sim_, kObserver);
        sim_.observers_.call(std::as_const(sim_));
    }

    double angle(int joint) const override { return sim_.angles_[static_cast<size_t>(joint)]; }
    double velocity(int joint) const override { return sim_.physics_->velocity(joint); }
    double torque(int joint) const override { return sim_.physics_->torque(joint); }

    // per global joint, copied from the spec so the hot loop reads flat arrays
    std::vector<ServoDef> servos_;
    std::vector<double> min_, max_;

  private:
    Simulation& sim_;
};

namespace {

// validated, newton_steps chosen for `world` where automatic
SimulationOptions checked(const SimulationOptions& o, const WorldSpec& world) {
    validate(o);
    SimulationOptions out = o;
    if (out.newton_steps == kAutomaticNewtonSteps)
        out.newton_steps = automatic_newton_steps(world, out.solver);
    return out;
}

}  // namespace

Simulation::Simulation(WorldSpec world, SimulationOptions options)
    : world_(std::move(world)),
      options_(checked(options, world_)),
      scheduler_(options_.dt, options_.control_every) {
    validate(world_);
    try {
        compile();
    } catch (const std::bad_alloc&) {
        release_controllers();
        throw out_of_memory();
    } catch (...) {
        release_controllers();
        throw;
    }
}

SimulationOptions Simulation::written_options() const {
    SimulationOptions o = options_;
    if (o.newton_steps == automatic_newton_steps(world_, o.solver))
        o.newton_steps = kAutomaticNewtonSteps;
    return o;
}

void Simulation::release_controllers() {
    // controllers may outlive the simulation (a Lua handle keeps them): stop telling it, and
    // let the next simulation bind them
    for (DriveSlot& d : drives_)
        d.drive.controller->unbind();
}

Error Simulation::out_of_memory() const {
    size_t bodies = 0;
    for (const PlacedRobot& r : world_.robots)
        bodies += r.robot.bodies.size();
    return Error(
        fmt::format("not enough memory to build the simulation ({} robots with {} "
                    "bodies, {} bodies of world objects)",
                    world_.robots.size(), bodies, solid_count(world_)));
}

void Simulation::compile() {
    phases_ = std::make_unique<Phases>(*this);
    int first_joint = 0;
    for (const PlacedRobot& r : world_.robots) {
        RobotSlot slot;
        slot.label = unique_label(r.robot.name);
        for (const JointSpec& j : r.robot.joints) {
            phases_->servos_.push_back(j.servo);
            phases_->min_.push_back(j.min_angle);
            phases_->max_.push_back(j.max_angle);
        }
        slot.first_joint = first_joint;
        first_joint += static_cast<int>(r.robot.joints.size());
        robots_.push_back(slot);
    }
    int first_body = 0;
    for (size_t r = 0; r < robots_.size(); ++r) {
        robots_[r].first_body = first_body;
        first_body += static_cast<int>(world_.robots[r].robot.bodies.size());
    }
    first_object_ = first_body;
    angles_.assign(static_cast<size_t>(first_joint), 0.0);
    targets_.assign(angles_.size(), 0.0);
    commands_.assign(angles_.size(), 0.0);
    energy_.assign(angles_.size(), 0.0);
    sensing_ = std::make_unique<Sensing>(world_, options_.dt);

    // bind every drive of the spec; the spec keeps them so reset() and copies see them too.
    // A controller another simulation binds already (one spec built twice) is copied fresh
    // for this one; one bound earlier in this loop (the same object in two groups) is not,
    // and add_drive says so
    std::set<const Controller*> mine;
    for (size_t r = 0; r < world_.robots.size(); ++r) {
        Actuation drives = std::move(world_.robots[r].actuation);
        world_.robots[r].actuation.clear();
        for (Drive& d : drives) {
            if (d.controller && d.controller->bound() && mine.count(d.controller.get()) == 0) {
                d.controller = std::shared_ptr<Controller>(d.controller->fresh_copy());
            }
            if (d.controller) mine.insert(d.controller.get());
            add_drive(static_cast<int>(r), std::move(d));
        }
    }
    build();
    check_start_overlaps();
    check_floor_sinking();
    for (std::string& w : accuracy_warnings(world_, options_))
        warnings_.push_back(std::move(w));
}

void Simulation::check_start_overlaps() {
    const auto o = physics_->deepest_robot_overlap(kMaxStartOverlap);
    if (!o) return;
    const std::string other = o->other_body >= 0 ? body_name(o->other_body) : o->other;
    warnings_.push_back(fmt::format(
        "{} starts {:.1f} mm deep inside {}: the contact solver will throw it out (place the "
        "robot clear of it, e.g. higher)",
        body_name(o->body), o->depth * 1000, other));
}

void Simulation::check_floor_sinking() {
    const FloorSpec& floor = world_.floor;
    if (!floor.enabled || floor.rigid) return;
    const double k = floor.stiffness.value_or(kDefaultFloorStiffness);
    const double g = world_.gravity.norm();
    // the body that sinks the largest part of its height: resting on `points` corners (a box
    // on a face's 4, a lying cylinder on 2) with its own weight on them
    struct Sink {
        std::string name;
        double mass = 0, height = 0, depth = 0;
    } worst;
    const auto consider = [&](const std::string& name, double mass, double height, int points) {
        const double depth = mass * g / (points * k);
        if (depth > kMaxFloorSink * height &&
            (worst.name.empty() || depth / height > worst.depth / worst.height)) {
            worst = {name, mass, height, depth};
        }
    };
    for (size_t r = 0; r < world_.robots.size(); ++r) {
        for (const BodySpec& b : world_.robots[r].robot.bodies) {
            const bool box = b.shape == Shape::box;
            consider(fmt::format("body '{}' of robot '{}'", b.name, robots_[r].label), b.mass,
                     box ? std::min({b.size.x, b.size.y, b.size.z}) : b.size.y, box ? 4 : 2);
        }
    }
    for (size_t i = 0; i < world_.boxes.size(); ++i) {
        const BoxSpec& b = world_.boxes[i];
        if (b.mass > 0) {
            consider(fmt::format("box {}", i + 1), b.mass, std::min({b.size.x, b.size.y, b.size.z}),
                     4);
        }
    }
    for (size_t i = 0; i < world_.cylinders.size(); ++i) {
        const CylinderSpec& c = world_.cylinders[i];
        if (c.mass > 0) {
            consider(fmt::format("cylinder {}", i + 1), c.mass, c.lying ? 2 * c.radius : c.length,
                     c.lying ? 2 : 4);
        }
    }
    if (worst.name.empty()) return;
    // the stiffness that would sink it by 1 % of its height
    const double enough = worst.depth * k / (0.01 * worst.height);
    warnings_.push_back(fmt::format(
        "{} ({:g} kg) sinks about {:.3g} mm into the floor, {:.0f} % of its height: the floor's "
        "springs ({:g} N/m per contact point) are soft for it (give the floor a stiffness of "
        "{:.2g} N/m or more)",
        worst.name, worst.mass, worst.depth * 1000, 100 * worst.depth / worst.height, k,
        std::min(enough, kMaxFloorStiffness)));
}

Simulation::~Simulation() {
    release_controllers();
}

std::string Simulation::unique_label(const std::string& base) {
    std::string label = base;
    for (int k = 2; !labels_.insert(label).second; ++k)
        label = fmt::format("{}_{}", base, k);
    return label;
}

void Simulation::build() {
    physics_ = std::make_unique<PhysicsWorld>(world_, options_.dt, options_.solver_iterations,
                                              options_.solver, options_.newton_steps);
    for (size_t r = 0; r < robots_.size(); ++r) {
        robots_[r].start_position = robot_position(static_cast<int>(r));
    }
    track_headings(true);
    std::fill(energy_.begin(), energy_.end(), 0.0);
    physics_->read_angles(angles_.data());
    sensing_->attach(*physics_);
    self_pass_every_ = !self_pass_warned_ && physics_->may_pass_through_itself()
                           ? self_pass_ticks(options_.dt)
                           : 0;
}

void Simulation::check_self_pass(double time) {
    const auto o = physics_->deepest_self_pass(kMaxSelfPass);
    if (!o) return;
    const size_t r = robot_of_body(o->body);
    const RobotSpec& robot = world_.robots[r].robot;
    warnings_.push_back(fmt::format(
        "robot '{}' passes through itself at t = {:.2f} s: its body '{}' is {:.1f} mm inside "
        "its body '{}' (a robot's bodies collide with each other only with self_collision = "
        "true)",
        robots_[r].label, time,
        robot.bodies[static_cast<size_t>(o->body - robots_[r].first_body)].name, o->depth * 1000,
        robot.bodies[static_cast<size_t>(o->other_body - robots_[r].first_body)].name));
    self_pass_warned_ = true;
    self_pass_every_ = 0;
    if (on_warning_) on_warning_(warnings_.back());
}

void Simulation::check_robot(int robot) const {
    if (robot < 0 || robot >= robot_count()) {
        throw SpecError(fmt::format("robot index {} out of range [0, {})", robot, robot_count()));
    }
}

void Simulation::check_drive(int drive) const {
    if (drive < 0 || drive >= drive_count()) {
        throw SpecError(fmt::format("drive index {} out of range [0, {})", drive, drive_count()));
    }
}

void Simulation::add_drive(int robot, Drive drive, Origin origin) {
    check_robot(robot);
    const PlacedRobot& placed = world_.robots[static_cast<size_t>(robot)];
    const int nj = static_cast<int>(placed.robot.joints.size());
    if (!drive.controller) throw SpecError("a drive needs a controller");
    if (drive.joints.empty()) throw SpecError("a joint group needs at least one joint");
    std::vector<int> sorted = drive.joints;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
        throw SpecError("a joint group names the same joint twice");
    }
    for (int j : drive.joints) {
        if (j < 0 || j >= nj) {
            throw SpecError(fmt::format("robot '{}' has no joint {} (it has joints 1 to {})",
                                        placed.robot.name, j + 1, nj));
        }
    }
    check_new_group(placed.actuation, drive, placed.robot.name);
    drive.controller->bind(static_cast<int>(drive.joints.size()));
    DriveSlot slot{robot,
                   drive,
                   {},
                   std::vector<double>(drive.joints.size(), 0.0),
                   unique_label(drive.controller->name())};
    for (int j : drive.joints)
        slot.global_joints.push_back(robots_[robot].first_joint + j);
    const int index = drive_count();
    drives_.push_back(std::move(slot));
    listen(index);
    world_.robots[static_cast<size_t>(robot)].actuation.push_back(std::move(drive));
    if (physics_) {  // not while the constructor binds the drives of the spec
        Event e;
        e.kind = EventKind::drive;
        e.origin = origin;
        e.name = drives_.back().label;
        e.drive = index;
        post_event(std::move(e));
    }
}

void Simulation::listen(int index) {
    // parameter changes become events stamped with the tick they act from
    Controller& c = *drives_[static_cast<size_t>(index)].drive.controller;
    c.set_param_listener([this, index](int param, double value, Origin o) {
        Event e;
        e.kind = EventKind::param;
        e.origin = o;
        e.name = drives_[static_cast<size_t>(index)].label + "." +
                 drives_[static_cast<size_t>(index)].drive.controller->def().params[param].name;
        e.value = value;
        e.drive = index;
        post_event(std::move(e));
    });
}

Simulation::Simulation(const Simulation& from, Copying, const SimulationOptions& options)
    : world_(from.world_), options_(options), scheduler_(from.scheduler_) {
    warnings_ = from.warnings_;
    const double dt_ratio = options_.dt / from.options_.dt;
    if (options_.dt != from.options_.dt || options_.control_every != from.options_.control_every) {
        // the same time in ticks of the new dt (clone(settings) checked it is whole)
        scheduler_ = Scheduler(options_.dt, options_.control_every);
        scheduler_.set_ticks(std::lround(static_cast<double>(from.ticks()) / dt_ratio));
    }
    if (options_.dt != from.options_.dt ||
        options_.solver_iterations != from.options_.solver_iterations ||
        options_.solver != from.options_.solver ||
        options_.newton_steps != from.options_.newton_steps) {
        // the warnings of the original's settings give way to those of the copy's
        for (const std::string& w : accuracy_warnings(world_, from.options_))
            warnings_.erase(std::remove(warnings_.begin(), warnings_.end(), w), warnings_.end());
        for (std::string& w : accuracy_warnings(world_, options_))
            warnings_.push_back(std::move(w));
    }
    self_pass_every_ = from.self_pass_every_ > 0 ? self_pass_ticks(options_.dt) : 0;
    self_pass_warned_ = from.self_pass_warned_;
    labels_ = from.labels_;
    robots_ = from.robots_;
    first_object_ = from.first_object_;
    angles_ = from.angles_;
    targets_ = from.targets_;
    commands_ = from.commands_;
    energy_ = from.energy_;
    phases_ = std::make_unique<Phases>(*this);
    phases_->servos_ = from.phases_->servos_;
    phases_->min_ = from.phases_->min_;
    phases_->max_ = from.phases_->max_;
    // every drive with a copy of its controller; the copy's spec holds the same copies, in
    // the same order
    for (PlacedRobot& r : world_.robots)
        r.actuation.clear();
    for (const DriveSlot& d : from.drives_) {
        DriveSlot slot = d;
        slot.drive.controller = std::shared_ptr<Controller>(d.drive.controller->clone());
        world_.robots[static_cast<size_t>(d.robot)].actuation.push_back(slot.drive);
        drives_.push_back(std::move(slot));
        listen(drive_count() - 1);
    }
    sensing_ = from.sensing_->copy();
    sensing_->set_dt(options_.dt);
    physics_ = std::make_unique<PhysicsWorld>(world_, options_.dt, options_.solver_iterations,
                                              options_.solver, options_.newton_steps);
    physics_->copy_state_from(*from.physics_, dt_ratio);
    sensing_->adopt(*physics_);
    paused_ = from.paused_;
}

std::unique_ptr<Simulation> Simulation::clone() {
    return clone(options_);
}

std::unique_ptr<Simulation> Simulation::clone(const SimulationOptions& settings) {
    check_idle("clone");
    SimulationOptions o = options_;
    o.dt = settings.dt;
    o.control_every = settings.control_every;
    o.solver_iterations = settings.solver_iterations;
    o.solver = settings.solver;
    o.newton_steps = settings.newton_steps;
    o = checked(o, world_);
    // the controllers step every control period, as they did: their state is per step
    const double period = options_.dt * options_.control_every;
    const double period_now = o.dt * o.control_every;
    if (std::abs(period_now - period) > 1e-9 * period) {
        throw SpecError(fmt::format(
            "cannot copy the simulation at dt = {:g} s, control_every = {}: the controllers "
            "step every {:g} s and a copy keeps that (dt x control_every = {:g} s; at dt = {:g} "
            "s, control_every = {:g})",
            o.dt, o.control_every, period, period_now, o.dt, period / o.dt));
    }
    // the time, a whole number of the new steps (as the copy counts them: ticks / ratio)
    const double steps = static_cast<double>(ticks()) / (o.dt / options_.dt);
    if (o.dt != options_.dt && (std::abs(steps - std::round(steps)) > 1e-6 + 1e-12 * steps ||
                                std::round(steps) > static_cast<double>(kMaxTicks))) {
        throw SpecError(fmt::format(
            "cannot copy the simulation at dt = {:g} s: its time, {:g} s ({} steps of {:g} s), "
            "is not a whole number of steps of {:g} s",
            o.dt, time(), ticks(), options_.dt, o.dt));
    }
    std::unique_ptr<Simulation> copy;
    std::unique_ptr<PhysicsWorld> rebuilt;
    try {
        copy.reset(new Simulation(*this, Copying{}, o));
        // the original goes on in a world rebuilt as the copy's was: Bullet's internal state
        // (broadphase trees, pair and manifold order) then matches the copy's exactly
        rebuilt = std::make_unique<PhysicsWorld>(world_, options_.dt, options_.solver_iterations,
                                                 options_.solver, options_.newton_steps);
        rebuilt->copy_state_from(*physics_);
    } catch (const std::bad_alloc&) {
        throw out_of_memory();
    }
    physics_ = std::move(rebuilt);
    sensing_->adopt(*physics_);
    return copy;
}

const std::string& Simulation::robot_label(int robot) const {
    check_robot(robot);
    return robots_[static_cast<size_t>(robot)].label;
}

const Controller& Simulation::controller(int drive) const {
    check_drive(drive);
    return *drives_[static_cast<size_t>(drive)].drive.controller;
}

Controller& Simulation::controller(int drive) {
    check_drive(drive);
    return *drives_[static_cast<size_t>(drive)].drive.controller;
}

int Simulation::drive_robot(int drive) const {
    check_drive(drive);
    return drives_[static_cast<size_t>(drive)].robot;
}

const std::vector<int>& Simulation::drive_joints(int drive) const {
    check_drive(drive);
    return drives_[static_cast<size_t>(drive)].drive.joints;
}

const std::string& Simulation::drive_label(int drive) const {
    check_drive(drive);
    return drives_[static_cast<size_t>(drive)].label;
}

size_t Simulation::robot_of_body(int body) const {
    size_t r = 0;
    while (r + 1 < robots_.size() && robots_[r + 1].first_body <= body)
        ++r;
    return r;
}

std::string Simulation::body_name(int body) const {
    // robot bodies come first, then the dynamic objects (boxes, cylinders)
    if (body < first_object_) {
        const size_t r = robot_of_body(body);
        const RobotSpec& robot = world_.robots[r].robot;
        return fmt::format("body '{}' of robot '{}'",
                           robot.bodies[static_cast<size_t>(body - robots_[r].first_body)].name,
                           robots_[r].label);
    }
    int k = body - first_object_;
    for (size_t i = 0; i < world_.boxes.size(); ++i) {
        if (world_.boxes[i].mass > 0 && k-- == 0) return fmt::format("box {}", i + 1);
    }
    for (size_t i = 0; i < world_.cylinders.size(); ++i) {
        if (world_.cylinders[i].mass > 0 && k-- == 0) return fmt::format("cylinder {}", i + 1);
    }
    return fmt::format("body {}", body);
}

void Simulation::diverged(int body, double time) const {
    const std::string name = body_name(body);
    const BodyState s = physics_->body(body);
    const Vec3& x = s.pose.position;
    using detail::shown;
    throw DivergenceError(fmt::format(
        "simulation diverged at t = {:.3f} s: {} is at ({}, {}, {}) m moving at {} m/s (try a "
        "smaller dt or more solver iterations)",
        time, name, shown(x.x), shown(x.y), shown(x.z), shown(s.linear_velocity.norm())));
}

void Simulation::fail(DriveSlot& d, const std::exception& e) {
    for (size_t m = 0; m < d.global_joints.size(); ++m) {
        d.targets[m] = angles_[static_cast<size_t>(d.global_joints[m])];
    }
    d.drive.controller->set_failed(true, e.what());
    if (options_.on_controller_error == ControllerErrorPolicy::stop) return;
    if (options_.on_controller_error == ControllerErrorPolicy::pause) pause_pending_ = true;
    if (on_error_) on_error_(*d.drive.controller, e);
}

void Simulation::check_idle(const char* what) const {
    // a pre-tick hook runs between ticks: it may reset (a replay applies a console's reset
    // there), but stepping from it would nest ticks
    const bool allowed = busy_ == kPreTick && std::string_view(what) == "reset";
    if (busy_ && !allowed) {
        throw SpecError(fmt::format(
            "cannot step the simulation from inside its own tick ({} called from {}: step, run, "
            "reset and clone belong between ticks)",
            what, busy_));
    }
}

long Simulation::step(long ticks) {
    check_idle("step");
    // within kMaxTicks in all: the tick counter never wraps and time stays exact
    checked_integer("ticks", ticks, 0, kMaxTicks - this->ticks());
    paused_ = false;
    for (long i = 0; i < ticks; ++i) {
        if (!pre_ticks_.idle()) {
            const Busy busy(*this, kPreTick);
            pre_ticks_.call(*this);
        }
        scheduler_.tick(*phases_);
        if (pause_pending_) {
            pause_pending_ = false;
            paused_ = true;
            return i + 1;
        }
    }
    return ticks;
}

long Simulation::ticks_for(double seconds) const {
    return checked_ticks("run time", seconds, options_.dt, ticks());
}

long Simulation::run(double seconds) {
    check_idle("run");
    return step(ticks_for(seconds));
}

void Simulation::reset(Origin origin) {
    check_idle("reset");
    const long at = ticks();
    scheduler_.reset();
    pause_pending_ = paused_ = false;
    for (DriveSlot& d : drives_) {
        d.drive.controller->set_failed(false);
        d.drive.controller->reset();
        std::fill(d.targets.begin(), d.targets.end(), 0.0);
    }
    std::fill(targets_.begin(), targets_.end(), 0.0);
    std::fill(commands_.begin(), commands_.end(), 0.0);
    try {
        build();
    } catch (const std::bad_alloc&) {
        throw out_of_memory();
    }
    // stamped with the tick it happened at, like every other event (a replay applies it there)
    Event e;
    e.kind = EventKind::reset;
    e.origin = origin;
    e.tick = at;
    dispatch(e);
}

Vec3 Simulation::robot_position(int robot) const {
    check_robot(robot);
    const RobotSpec& spec = world_.robots[static_cast<size_t>(robot)].robot;
    Vec3 sum;
    for (size_t b = 0; b < spec.bodies.size(); ++b) {
        sum += physics_->position(robots_[robot].first_body + static_cast<int>(b)) *
               spec.bodies[b].mass;
    }
    return sum * (1.0 / total_mass(spec));
}

Vec3 Simulation::robot_velocity(int robot) const {
    check_robot(robot);
    const RobotSpec& spec = world_.robots[static_cast<size_t>(robot)].robot;
    Vec3 sum;
    for (size_t b = 0; b < spec.bodies.size(); ++b) {
        sum += physics_->mass_velocity(robots_[robot].first_body + static_cast<int>(b)) *
               spec.bodies[b].mass;
    }
    return sum * (1.0 / total_mass(spec));
}

Vec3 Simulation::robot_displacement(int robot) const {
    return robot_position(robot) - robots_[static_cast<size_t>(robot)].start_position;
}

double Simulation::heading_now(int robot, double previous) const {
    const RobotSlot& slot = robots_[static_cast<size_t>(robot)];
    const int n = static_cast<int>(world_.robots[static_cast<size_t>(robot)].robot.bodies.size());
    // the direction from the tail's shape to the head's (their centres of mass may lie aside)
    const Vec3 tail = physics_->shape_position(slot.first_body);
    const Vec3 d = physics_->shape_position(slot.first_body + n - 1) - tail;
    // a robot standing on its tail has no tail-to-head direction on the floor
    constexpr double kVertical = 1e-9;
    if (std::hypot(d.x, d.y) > kVertical) return std::atan2(d.y, d.x);
    const Vec3 x = physics_->body(slot.first_body).pose.orientation.rotate(Vec3{1, 0, 0});
    if (std::hypot(x.x, x.y) > kVertical) return std::atan2(x.y, x.x);
    return previous;
}

void Simulation::track_headings(bool start) {
    constexpr double kTurn = 2 * 3.14159265358979323846;
    for (size_t r = 0; r < robots_.size(); ++r) {
        RobotSlot& slot = robots_[r];
        const double h = heading_now(static_cast<int>(r), slot.heading);
        if (start) {
            slot.turned = 0;
        } else {
            // the change since the last tick, taken the short way round
            slot.turned += std::remainder(h - slot.heading, kTurn);
        }
        slot.heading = h;
    }
}

void Simulation::integrate_energy() {
    // every physics step, recorded or not, so every recording of this simulation (and of its
    // clones) reads the same energy at the same time
    const double dt = options_.dt;
    for (size_t j = 0; j < energy_.size(); ++j) {
        const int g = static_cast<int>(j);
        energy_[j] += std::abs(physics_->torque(g) * physics_->velocity(g)) * dt;
    }
}

double Simulation::robot_heading(int robot) const {
    check_robot(robot);
    return robots_[static_cast<size_t>(robot)].heading;
}

double Simulation::robot_turned(int robot) const {
    check_robot(robot);
    return robots_[static_cast<size_t>(robot)].turned;
}

BodyState Simulation::body(int robot, int b) const {
    check_robot(robot);
    const int n = static_cast<int>(world_.robots[static_cast<size_t>(robot)].robot.bodies.size());
    if (b < 0 || b >= n) throw SpecError(fmt::format("body index {} out of range [0, {})", b, n));
    return physics_->body(robots_[robot].first_body + b);
}

JointState Simulation::joint(int robot, int j) const {
    check_robot(robot);
    const int n = static_cast<int>(world_.robots[static_cast<size_t>(robot)].robot.joints.size());
    if (j < 0 || j >= n) throw SpecError(fmt::format("joint index {} out of range [0, {})", j, n));
    const int g = robots_[robot].first_joint + j;
    JointState s;
    s.angle = physics_->angle(g);
    s.target = targets_[static_cast<size_t>(g)];
    s.velocity = physics_->velocity(g);
    s.torque = physics_->torque(g);
    return s;
}

void Simulation::joint_powers(int robot, double* out) const {
    check_robot(robot);
    const int n = static_cast<int>(world_.robots[static_cast<size_t>(robot)].robot.joints.size());
    const int first = robots_[static_cast<size_t>(robot)].first_joint;
    for (int j = 0; j < n; ++j)
        out[j] = physics_->torque(first + j) * physics_->velocity(first + j);
}

void Simulation::joint_energies(int robot, double* out) const {
    check_robot(robot);
    const size_t n = world_.robots[static_cast<size_t>(robot)].robot.joints.size();
    const auto first = energy_.begin() + robots_[static_cast<size_t>(robot)].first_joint;
    std::copy(first, first + static_cast<std::ptrdiff_t>(n), out);
}

double Simulation::robot_energy(int robot) const {
    check_robot(robot);
    const size_t n = world_.robots[static_cast<size_t>(robot)].robot.joints.size();
    const auto first = energy_.begin() + robots_[static_cast<size_t>(robot)].first_joint;
    double total = 0;
    for (auto e = first; e != first + static_cast<std::ptrdiff_t>(n); ++e)
        total += *e;
    return total;
}

JointError Simulation::joint_error(int robot, int j) const {
    check_robot(robot);
    const int n = static_cast<int>(world_.robots[static_cast<size_t>(robot)].robot.joints.size());
    if (j < 0 || j >= n) throw SpecError(fmt::format("joint index {} out of range [0, {})", j, n));
    return physics_->joint_error(robots_[robot].first_joint + j);
}

int Simulation::object_count() const {
    return physics_->body_count() - first_object_;
}

BodyState Simulation::object(int index) const {
    const int n = object_count();
    if (index < 0 || index >= n) {
        throw SpecError(fmt::format("object index {} out of range [0, {})", index, n));
    }
    return physics_->body(first_object_ + index);
}

int Simulation::contact_count() const {
    return physics_->contact_count();
}

void Simulation::contacts(std::vector<ContactPoint>& out) const {
    physics_->contacts(out, options_.dt);
}

void Simulation::check_sensor(int i) const {
    if (i < 0 || i >= sensor_count()) {
        throw SpecError(fmt::format("sensor index {} out of range [0, {})", i, sensor_count()));
    }
}

int Simulation::sensor_count() const {
    return sensing_->count();
}

const SensorSpec& Simulation::sensor(int i) const {
    check_sensor(i);
    return sensing_->spec(i);
}

int Simulation::sensor_robot(int i) const {
    check_sensor(i);
    return sensing_->robot(i);
}

int Simulation::find_sensor(int robot, std::string_view name) const {
    check_robot(robot);
    return sensing_->find(robot, name);
}

int Simulation::sensor_index(int robot, int k) const {
    check_robot(robot);
    const int n = sensing_->robot_sensor_count(robot);
    if (k < 0 || k >= n) {
        throw SpecError(fmt::format("robot sensor index {} out of range [0, {})", k, n));
    }
    return sensing_->index(robot, k);
}

const std::vector<SensorChannel>& Simulation::sensor_channels(int i) const {
    return gaitlab::sensor_channels(sensor(i).kind);
}

const std::vector<double>& Simulation::sensor_values(int i) const {
    check_sensor(i);
    return sensing_->values(i);
}

bool Simulation::sensor_enabled(int i) const {
    return sensor(i).enabled;
}

void Simulation::set_sensor_enabled(int i, bool on, Origin origin) {
    check_sensor(i);
    if (sensor_enabled(i) == on) return;  // no change, no event
    sensing_->set_enabled(i, on, *physics_);
    // the spec follows, so reset() and a copy of world() keep the switch
    const int r = sensing_->robot(i);
    RobotSpec& robot = world_.robots[static_cast<size_t>(r)].robot;
    SensorSpec& spec = robot.sensors[static_cast<size_t>(sensing_->local_index(i))];
    spec.enabled = on;
    Event e;
    e.kind = EventKind::sensor;
    e.origin = origin;
    e.name = robot_label(r) + "." + sensor_name(spec);
    e.value = on ? 1 : 0;
    post_event(std::move(e));
}

int Simulation::find_sensor(std::string_view label) const {
    for (int i = 0; i < sensor_count(); ++i) {
        if (label == robot_label(sensor_robot(i)) + "." + sensor_name(sensor(i))) return i;
    }
    return -1;
}

int Simulation::add_sensor(int robot, SensorSpec sensor) {
    check_robot(robot);
    RobotSpec& spec = world_.robots[static_cast<size_t>(robot)].robot;
    validate_sensor(spec, sensor);
    const int i = sensing_->add(robot, sensor, *physics_);
    spec.sensors.push_back(std::move(sensor));
    return i;
}

int Simulation::add_observer(std::function<void(const Simulation&)> fn) {
    observers_.add(next_observer_, std::move(fn));
    return next_observer_++;
}

void Simulation::remove_observer(int id) {
    observers_.remove(id);
}

int Simulation::add_pre_tick(std::function<void(Simulation&)> fn) {
    pre_ticks_.add(next_observer_, std::move(fn));
    return next_observer_++;
}

void Simulation::remove_pre_tick(int id) {
    pre_ticks_.remove(id);
}

int Simulation::add_event_listener(std::function<void(const Simulation&, const Event&)> fn) {
    listeners_.add(next_observer_, std::move(fn));
    return next_observer_++;
}

void Simulation::remove_event_listener(int id) {
    listeners_.remove(id);
}

void Simulation::post_event(Event event) {
    event.tick = ticks();
    dispatch(event);
}

void Simulation::dispatch(const Event& event) {
    const Busy busy(*this, kListener);
    listeners_.call(std::as_const(*this), event);
}

}  // namespace gaitlab
