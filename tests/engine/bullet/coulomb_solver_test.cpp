// The block methods' three paths (engine/src/bullet/coulomb_solver.h, BlockPath): the fast band
// of a chain of hinges, the band with the generic loops, and the profile. They take every sum
// in the same order, so a chain gives the same bits on each: stepped here through each path
// (CoulombSolver::force_block_path, a test hook), with the engine's real world and solver. And
// the profile where the engine takes it by itself: a robot with a body of three hinges.
// The band's generic path is never taken by itself in the engine: it needs a fixed body or
// factors other than 1 in a chain's rows, and a robot's bodies all have a positive mass
// (validate_body) and are joined only to each other (no joint to the world). So it is taken
// here by itself on Bullet directly: arms hung from a fixed body.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bullet/coulomb_solver.h"
#include "bullet/physics_world.h"
#include "engine/sim_support.h"
#include "gaitlab/servo.h"
#include "gaitlab/urdf.h"

using namespace gaitlab;

namespace {

constexpr double kDt = 0.001;      // s, the engine's default step
constexpr int kIterations = 20;    // the engine's default solver iterations
constexpr int kControlEvery = 30;  // ticks between target updates, the engine's default

// the sine generator's law (controllers/src/sine.cpp): for the m-th joint of its group (m
// from 0), A sin(2 pi f t + m dphi + phi0), degrees in, radians out
struct SineDrive {
    std::vector<int> joints;
    double amplitude = 40, frequency = 0.5, phase = 120, phase0 = 0;
};

double sine_target(const SineDrive& d, int m, double t) {
    return deg_to_rad(d.amplitude *
                      std::sin(2 * kPi * d.frequency * t + deg_to_rad(m * d.phase + d.phase0)));
}

CoulombSolver& solver_of(const PhysicsWorld& w) {
    return static_cast<CoulombSolver&>(*w.bullet_world().getConstraintSolver());
}

// what a run saw: every body's state at every control tick, each joint's largest separation,
// the paths the solver's factor took, and each driven joint's angle against its target
struct Run {
    std::vector<BodyState> states;
    double max_separation = 0;     // m, the largest of any joint after any step
    double mean_separation = 0;    // m, the mean over the steps of the largest of any joint
    bool diverged = false;         // some body's state was not finite, far off or too fast
    std::vector<BlockPath> paths;  // the distinct paths, in the order first seen
    double max_lag = 0;            // rad, |target - angle| at the control ticks of the last 2 s
    std::vector<double> min_angle, max_angle;  // rad, per joint, over the last 2 s
    Vec3 start, end;                           // the first body's position, m
};

// steps `world` as Simulation does (sense, targets every kControlEvery ticks, servo commands,
// physics) for `steps` steps with the drives given, the solver `solver` forced onto `path`
Run run(const WorldSpec& world, const std::vector<SineDrive>& drives, int steps,
        ConstraintSolver solver, BlockPath path = BlockPath::automatic) {
    PhysicsWorld w(world, kDt, kIterations, solver);
    solver_of(w).force_block_path(path);
    const RobotSpec& robot = world.robots[0].robot;
    const int joints = w.joint_count();
    std::vector<double> angles(static_cast<size_t>(joints)), targets(angles.size(), 0.0),
        commands(angles.size());
    Run r;
    r.min_angle.assign(angles.size(), 1e9);
    r.max_angle.assign(angles.size(), -1e9);
    r.start = w.position(0);
    const int last_cycle = steps - static_cast<int>(2 / kDt);  // a cycle of the 0.5 Hz gaits
    for (int tick = 0; tick < steps; ++tick) {
        w.read_angles(angles.data());
        if (tick % kControlEvery == 0) {
            const double t = tick * kDt;
            if (tick >= last_cycle) {
                for (const SineDrive& d : drives) {
                    for (int j : d.joints)
                        r.max_lag = std::max(r.max_lag, std::abs(targets[j] - angles[j]));
                }
            }
            for (const SineDrive& d : drives) {
                for (size_t m = 0; m < d.joints.size(); ++m)
                    targets[d.joints[m]] = sine_target(d, static_cast<int>(m), t);
            }
            for (int b = 0; b < w.body_count(); ++b)
                r.states.push_back(w.body(b));
        }
        for (int j = 0; j < joints; ++j) {
            commands[j] = servo_command(robot.joints[j].servo, targets[j], angles[j]);
            if (tick >= last_cycle) {
                r.min_angle[j] = std::min(r.min_angle[j], angles[j]);
                r.max_angle[j] = std::max(r.max_angle[j], angles[j]);
            }
        }
        w.set_motor_velocities(commands.data());
        w.step(kDt);
        if (solver == ConstraintSolver::block_nncg &&
            std::find(r.paths.begin(), r.paths.end(), solver_of(w).block_path()) == r.paths.end())
            r.paths.push_back(solver_of(w).block_path());
        r.diverged = r.diverged || w.first_diverged(100, 100) >= 0;
        double separation = 0;
        for (int j = 0; j < joints; ++j) {
            const double e = w.joint_error(j).separation;
            separation = std::isnan(e) ? e : std::max(separation, e);  // NaN stays
        }
        r.max_separation =
            std::isnan(separation) ? separation : std::max(r.max_separation, separation);
        r.mean_separation += separation / steps;
    }
    for (int b = 0; b < w.body_count(); ++b)
        r.states.push_back(w.body(b));
    r.end = w.position(0);
    return r;
}

bool same_bits(const BodyState& a, const BodyState& b) {
    return a.pose.position == b.pose.position && a.pose.orientation == b.pose.orientation &&
           a.linear_velocity == b.linear_velocity && a.angular_velocity == b.angular_velocity;
}

// the index of the first state where two runs differ, -1 if none (and as many states)
long first_difference(const Run& a, const Run& b) {
    if (a.states.size() != b.states.size()) return 0;
    for (size_t k = 0; k < a.states.size(); ++k) {
        if (!same_bits(a.states[k], b.states[k])) return static_cast<long>(k);
    }
    return -1;
}

const char* name(BlockPath p) {
    switch (p) {
        case BlockPath::automatic:
            return "automatic";
        case BlockPath::band_fast:
            return "band_fast";
        case BlockPath::band_generic:
            return "band_generic";
        case BlockPath::profile:
            return "profile";
    }
    return "?";
}

std::string names(const std::vector<BlockPath>& paths) {
    std::string s;
    for (BlockPath p : paths)
        s += std::string(s.empty() ? "" : " ") + name(p);
    return s;
}

// the standard gaits of the engine tests (sim_support.h): pitch-pitch A 40 deg, 0.5 Hz, 120 deg
// between neighbours; pitch-yaw the same on the pitch joints, the yaw joints A 30 deg with
// phase0 90 deg (drive_pitch_yaw_gait)
std::vector<SineDrive> chain_gait(const RobotSpec& robot, Connection c) {
    SineDrive pitch;
    pitch.joints = select_joints(robot, "pitch");
    if (c == Connection::pitch_pitch) return {pitch};
    SineDrive yaw;
    yaw.joints = select_joints(robot, "yaw");
    yaw.amplitude = 30;
    yaw.phase0 = 90;
    return {pitch, yaw};
}

// a star: a centre body (a y1 module's 72 x 72 x 52 mm, 50 g) and three legs at 0, 120 and 240
// degrees about z, each two 72 mm bodies of 50 g joined to the centre and to each other by
// pitch hinges (axes horizontal, across the leg), so the centre holds three hinges
WorldSpec star_world() {
    RobotSpec robot;
    robot.name = "star";
    const double len = 0.072, width = 0.052, z = width / 2;
    auto add_body = [&](const std::string& name, double x, double y, double yaw, Vec3 size) {
        BodySpec b;
        b.name = name;
        b.size = size;
        b.mass = 0.05;
        b.pose.position = {x, y, z};
        b.pose.orientation = Quat::from_axis_angle({0, 0, 1}, yaw);
        robot.bodies.push_back(b);
    };
    add_body("centre", 0, 0, 0, {len, len, width});
    for (int leg = 0; leg < 3; ++leg) {
        const double yaw = deg_to_rad(120.0 * leg);
        const Vec3 d{std::cos(yaw), std::sin(yaw), 0};
        for (int k = 0; k < 2; ++k) {
            const double r = len / 2 + len * (k + 0.5);  // the body's centre from the star's
            add_body("leg" + std::to_string(leg + 1) + "_" + std::to_string(k + 1), d.x * r,
                     d.y * r, yaw, {len, width, width});
            JointSpec j;
            j.name = "joint" + std::to_string(leg + 1) + "_" + std::to_string(k + 1);
            j.role = JointRole::pitch;
            j.parent = k == 0 ? 0 : static_cast<int>(robot.bodies.size()) - 2;
            j.child = static_cast<int>(robot.bodies.size()) - 1;
            const double at = len / 2 + len * k;  // the pivot from the star's centre
            j.pivot = {d.x * at, d.y * at, z};
            j.axis = d.cross({0, 0, 1});  // a positive angle lifts the leg's outer side
            j.min_angle = deg_to_rad(-90);
            j.max_angle = deg_to_rad(90);
            robot.joints.push_back(j);
        }
    }
    validate(robot);
    return test::world_of(std::move(robot));
}

// After one step of `iterations` from the star's rest pose, floating (no gravity, no floor),
// every body given a random velocity and the motors off (so the joints' equality rows are the
// only rows): the largest violation of those rows by the velocities the step left, at the pose
// the rows were built at: each pivot's velocity seen from its two bodies (m/s) and their
// angular velocity across the hinge's axis (rad/s), the larger of the two; and the path the
// solver took.
struct Residual {
    double worst = 0;
    BlockPath path = BlockPath::automatic;
};

Residual star_joint_residual(ConstraintSolver solver, int iterations) {
    WorldSpec world = star_world();
    world.gravity = {0, 0, 0};
    world.floor.enabled = false;
    const RobotSpec& robot = world.robots[0].robot;
    PhysicsWorld w(world, kDt, iterations, solver);
    btDiscreteDynamicsWorld& bullet = w.bullet_world();
    for (int i = 0; i < bullet.getNumConstraints(); ++i)
        static_cast<btHingeConstraint*>(bullet.getConstraint(i))->enableMotor(false);
    std::mt19937 rng(7);
    std::uniform_real_distribution<btScalar> u(-1, 1);
    for (int b = 0; b < w.body_count(); ++b) {
        w.bullet_body(b).setLinearVelocity(btVector3(u(rng), u(rng), u(rng)) * btScalar(0.5));
        w.bullet_body(b).setAngularVelocity(btVector3(u(rng), u(rng), u(rng)) * btScalar(5));
    }
    w.step(kDt);
    Residual r;
    r.path = solver_of(w).block_path();
    for (const JointSpec& j : robot.joints) {
        const BodyState a = w.body(j.child), b = w.body(j.parent);
        const Vec3 ra = j.pivot - robot.bodies[static_cast<size_t>(j.child)].pose.position;
        const Vec3 rb = j.pivot - robot.bodies[static_cast<size_t>(j.parent)].pose.position;
        const Vec3 slip = a.linear_velocity + a.angular_velocity.cross(ra) -
                          (b.linear_velocity + b.angular_velocity.cross(rb));
        const Vec3 turn = a.angular_velocity - b.angular_velocity;
        const Vec3 across = turn - j.axis * turn.dot(j.axis);
        r.worst = std::max({r.worst, slip.norm(), across.norm()});
    }
    return r;
}

// Two arms hung from a fixed body, on Bullet directly (a robot cannot be fixed to the world):
// each two boxes of 72 x 52 x 52 mm and 50 g hinged end to end about y, the first to a static
// anchor between the arms, held out horizontally (to -x and +x) at the start and swinging down
// under gravity, no contacts. The anchor is Bullet's fixed solver body (no m_originalBody), so
// the hinges' band takes the generic loops by itself, and the second arm's first group shares
// no moving body with the group before it (the first arm's last).
class HangingArms {
  public:
    static constexpr int kLinks = 4;          // two per arm: -x inner, outer, +x inner, outer
    static constexpr double kLength = 0.072;  // m

    HangingArms(SolverMethod method, BlockPath path) {
        solver_.set_method(method);
        solver_.force_block_path(path);
        world_.setGravity(btVector3(0, 0, btScalar(-9.81)));
        world_.getSolverInfo().m_numIterations = kIterations;
        const btScalar length = btScalar(kLength);
        shape_ =
            std::make_unique<btBoxShape>(btVector3(length / 2, btScalar(0.026), btScalar(0.026)));
        add(0, btVector3(0, 0, 0));  // the anchor
        for (int k = 0; k < kLinks; ++k) {
            const btScalar side = k < 2 ? -1 : 1;
            const btScalar outer = btScalar(k % 2);  // 1 for the outer link, 0 for the inner
            add(btScalar(0.05), btVector3(side * (length / 2 + length * outer), 0, 0));
            // the inner link hinged to the anchor, the outer to the inner
            btRigidBody& a = *bodies_.back();
            btRigidBody& b = *bodies_[k % 2 == 0 ? 0 : bodies_.size() - 2];
            const btVector3 pivot(side * length * outer, 0, 0), axis(0, 1, 0);
            hinges_.push_back(std::make_unique<btHingeConstraint>(
                a, b, a.getWorldTransform().inverse() * pivot,
                b.getWorldTransform().inverse() * pivot, axis, axis));
            hinges_.back()->setUserConstraintId(k);
            world_.addConstraint(hinges_.back().get(), true);
        }
    }
    ~HangingArms() {
        for (auto& h : hinges_)
            world_.removeConstraint(h.get());
        for (auto& b : bodies_)
            world_.removeRigidBody(b.get());
    }
    HangingArms(const HangingArms&) = delete;
    HangingArms& operator=(const HangingArms&) = delete;

    void step() { world_.stepSimulation(btScalar(kDt), 0); }
    BlockPath path() const { return solver_.block_path(); }
    const btRigidBody& link(int k) const { return *bodies_[static_cast<size_t>(k) + 1]; }
    /// the largest distance between a hinge's pivot seen from its two bodies, m
    double separation() const {
        double worst = 0;
        for (const auto& h : hinges_) {
            const btVector3 a = h->getRigidBodyA().getWorldTransform() * h->getAFrame().getOrigin();
            const btVector3 b = h->getRigidBodyB().getWorldTransform() * h->getBFrame().getOrigin();
            worst = std::max(worst, static_cast<double>((a - b).length()));
        }
        return worst;
    }

  private:
    void add(btScalar mass, const btVector3& at) {
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape_->calculateLocalInertia(mass, inertia);
        btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape_.get(), inertia);
        info.m_startWorldTransform.setOrigin(at);
        bodies_.push_back(std::make_unique<btRigidBody>(info));
        bodies_.back()->setUserIndex(static_cast<int>(bodies_.size()) - 1);
        bodies_.back()->setActivationState(DISABLE_DEACTIVATION);
        world_.addRigidBody(bodies_.back().get(), 0, 0);  // collides with nothing
    }

    CoulombSolver solver_;
    btDefaultCollisionConfiguration config_;
    btCollisionDispatcher dispatcher_{&config_};
    btDbvtBroadphase broadphase_;
    btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
    std::unique_ptr<btBoxShape> shape_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<std::unique_ptr<btHingeConstraint>> hinges_;
};

// the hanging arms stepped `steps` times: each link's position and velocities every 10 steps,
// the paths taken, the largest separation, the lowest an outer link went
struct Swing {
    std::vector<btVector3> states;
    std::vector<BlockPath> paths;
    double max_separation = 0;  // m
    double lowest = 0;          // m, z of an outer link's centre
};

Swing swing(SolverMethod method, BlockPath path, int steps) {
    HangingArms arms(method, path);
    Swing s;
    for (int i = 1; i <= steps; ++i) {
        arms.step();
        if (std::find(s.paths.begin(), s.paths.end(), arms.path()) == s.paths.end())
            s.paths.push_back(arms.path());
        const double e = arms.separation();
        s.max_separation = std::isnan(e) ? e : std::max(s.max_separation, e);
        if (i % 10 != 0) continue;
        for (int k = 0; k < HangingArms::kLinks; ++k) {
            const btRigidBody& b = arms.link(k);
            if (k % 2 == 1)
                s.lowest = std::min(s.lowest, static_cast<double>(b.getCenterOfMassPosition().z()));
            s.states.push_back(b.getCenterOfMassPosition());
            s.states.push_back(b.getLinearVelocity());
            s.states.push_back(b.getAngularVelocity());
        }
    }
    return s;
}

}  // namespace

TEST_CASE(
    "block_nncg gives the same bits on a chain through the fast band, the generic band "
    "and the profile") {
    const Connection connection = GENERATE(Connection::pitch_pitch, Connection::pitch_yaw);
    CAPTURE(to_string(connection));
    const WorldSpec world = test::chain_world(8, connection);
    const std::vector<SineDrive> gait = chain_gait(world.robots[0].robot, connection);
    const int steps = 1500;  // 1.5 s, three quarters of a cycle of the gait
    const Run fast = run(world, gait, steps, ConstraintSolver::block_nncg);
    const Run generic =
        run(world, gait, steps, ConstraintSolver::block_nncg, BlockPath::band_generic);
    const Run profile = run(world, gait, steps, ConstraintSolver::block_nncg, BlockPath::profile);
    // each run took its path at every step, and only it
    CHECK(names(fast.paths) == "band_fast");
    CHECK(names(generic.paths) == "band_generic");
    CHECK(names(profile.paths) == "profile");
    // the robot moved, and the solver matters: pgs gives other bits
    CHECK_FALSE(fast.diverged);
    CHECK((fast.end - fast.start).norm() > 0.002);
    const Run pgs = run(world, gait, steps, ConstraintSolver::pgs);
    CHECK(first_difference(fast, pgs) >= 0);
    // every body's position, orientation and velocities at every control tick, bit for bit
    CHECK(first_difference(fast, generic) == -1);
    CHECK(first_difference(fast, profile) == -1);
}

TEST_CASE(
    "block_nncg takes the profile on a robot with a body of three hinges, holds it "
    "together, drives its joints and repeats its bits") {
    const WorldSpec world = star_world();
    const RobotSpec& robot = world.robots[0].robot;
    // the legs' inner joints one wave, the outer ones the same a quarter period apart
    SineDrive inner, outer;
    for (int leg = 0; leg < 3; ++leg) {
        inner.joints.push_back(2 * leg);
        outer.joints.push_back(2 * leg + 1);
    }
    inner.amplitude = 30;
    outer.amplitude = 30;
    outer.phase0 = 90;
    const std::vector<SineDrive> drives{inner, outer};
    const int steps = 4000;  // 4 s, two cycles
    const Run block = run(world, drives, steps, ConstraintSolver::block_nncg);
    CHECK(names(block.paths) == "profile");
    CHECK_FALSE(block.diverged);
    // deterministic: a second run gives the same bits
    const Run again = run(world, drives, steps, ConstraintSolver::block_nncg);
    CHECK(first_difference(block, again) == -1);
    // held together as pgs holds it, or better (measured: the joints' largest separation
    // 28 um at most, 5.8 um on average over the steps with block_nncg; 31 and 14 um with pgs;
    // the largest of both while the star settles onto the floor in the first 0.25 s)
    const Run pgs = run(world, drives, steps, ConstraintSolver::pgs);
    CAPTURE(block.max_separation, pgs.max_separation, block.mean_separation, pgs.mean_separation);
    CHECK(block.max_separation < 50e-6);
    CHECK(block.mean_separation < pgs.mean_separation);
    // driven: over the last cycle each joint swings through most of its +-30 deg and lags
    // its target as the servo does under pgs
    for (int j = 0; j < static_cast<int>(robot.joints.size()); ++j) {
        CAPTURE(j, rad_to_deg(block.min_angle[j]), rad_to_deg(block.max_angle[j]));
        CHECK(block.max_angle[j] - block.min_angle[j] > deg_to_rad(40));
        CHECK(block.max_angle[j] < deg_to_rad(32));
        CHECK(block.min_angle[j] > deg_to_rad(-32));
    }
    CAPTURE(rad_to_deg(block.max_lag), rad_to_deg(pgs.max_lag));
    CHECK(block.max_lag < deg_to_rad(15));
    CHECK(block.max_lag < pgs.max_lag + deg_to_rad(2));
}

TEST_CASE(
    "block_nncg's profile solves the joint rows of a body of three hinges exactly in one "
    "iteration") {
    // bodies at up to 0.5 m/s and 5 rad/s (0.2 m/s at the pivots from the turning), one
    // iteration: the block's rows are solved exactly, to float's rounding (measured: 8.7e-6,
    // m/s or rad/s), where one sweep of pgs leaves 14 (and the profile with half of K's
    // coupling terms 5.5)
    const Residual block = star_joint_residual(ConstraintSolver::block_nncg, 1);
    const Residual pgs = star_joint_residual(ConstraintSolver::pgs, 1);
    CHECK(name(block.path) == std::string("profile"));
    CAPTURE(block.worst, pgs.worst);
    CHECK(block.worst < 1e-4);
    CHECK(pgs.worst > 100 * block.worst);
}

// One step of `iterations` of a floating 4-module pitch-pitch chain (no gravity, no floor: the
// joints' rows are the only rows), at rest, its motors commanded to turn the joints at 1.2,
// -2, 1.5 and 0.8 rad/s, joint 2's servo allowed only 1e-4 N m: what each joint turned at (its
// measured speed after the step, rad/s) and the motor torque it took (N m).
struct MotorStep {
    std::vector<double> speed, torque;
    std::vector<double> command = {1.2, -2.0, 1.5, 0.8};
    static constexpr int kWeak = 1;              // joint 2, counted from 0
    static constexpr double kWeakTorque = 1e-4;  // N m
};

MotorStep motor_step(ConstraintSolver solver, int iterations) {
    WorldSpec world = test::chain_world(4, Connection::pitch_pitch, false);
    world.robots[0].robot.joints[MotorStep::kWeak].servo.max_torque = MotorStep::kWeakTorque;
    PhysicsWorld w(world, kDt, iterations, solver);
    MotorStep m;
    w.set_motor_velocities(m.command.data());
    w.step(kDt);
    for (int j = 0; j < w.joint_count(); ++j) {
        m.speed.push_back(w.velocity(j));
        m.torque.push_back(w.torque(j));
    }
    return m;
}

TEST_CASE(
    "block_nncg turns every motor's joint at its command in one iteration and holds one that "
    "needs more than its torque at the limit") {
    // the motors' rows are in the block (coulomb_solver.h, solve_block): one iteration solves
    // them exactly with the hinges' other rows; the weak motor cannot turn its joint at -2
    // rad/s with 1e-4 N m, so it is held at its limit and leaves the block, and the others
    // are solved again without it (measured: the strong joints within 1e-7 of their
    // commands, the weak one turned by its neighbours at -1.54 rad/s; pgs's one sweep leaves
    // the strong joints up to 37 % off)
    const MotorStep block = motor_step(ConstraintSolver::block_nncg, 1);
    const MotorStep pgs = motor_step(ConstraintSolver::pgs, 1);
    double block_off = 0, pgs_off = 0;
    for (int j = 0; j < 4; ++j) {
        CAPTURE(j, block.speed[j], block.torque[j], pgs.speed[j], pgs.torque[j]);
        if (j == MotorStep::kWeak) {
            // the torque as the joint's feedback gives it back (a difference of moments: its
            // rounding is 1e-5 of the limit)
            CHECK(std::abs(block.torque[j]) <= MotorStep::kWeakTorque * (1 + 1e-4));
            CHECK(std::abs(block.torque[j]) >= MotorStep::kWeakTorque * (1 - 1e-4));
            CHECK(std::abs(block.speed[j] / block.command[j] - 1) > 0.1);
            continue;
        }
        block_off = std::max(block_off, std::abs(block.speed[j] / block.command[j] - 1));
        pgs_off = std::max(pgs_off, std::abs(pgs.speed[j] / pgs.command[j] - 1));
    }
    CAPTURE(block_off, pgs_off);
    CHECK(block_off < 1e-4);
    CHECK(pgs_off > 0.05);
}

// The performance anchors' pitch-yaw snake (bench/lua/anchor_snake.lua, docs/performance.md
// section 13): 8 boxes of 72 x 52 x 52 mm and 50 g in a row, head (body 0) at x = 0, hinges
// through the centres of the shared faces, pitch and yaw alternating from the head, servos of
// kp 20, 5.2 rad/s and 0.3 N m, floor friction 0.8; pitch 40 deg and yaw 20 deg sines at 0.5 Hz,
// 120 deg between neighbours of a group, updated every 10 ms. Its head's per-cycle speed, mm:
// the mean length of the head's displacement over cycles 2 to 11 (issue 14's measure).
double anchor_snake_speed(ConstraintSolver solver, double dt, int iterations) {
    RobotSpec robot;
    robot.name = "snake";
    const double len = 0.072, width = 0.052;
    for (int i = 0; i < 8; ++i) {
        BodySpec b;
        b.name = "m" + std::to_string(i);
        b.size = {len, width, width};
        b.mass = 0.05;
        b.pose.position = {-i * len, 0, width / 2};
        robot.bodies.push_back(b);
    }
    for (int j = 0; j < 7; ++j) {
        JointSpec joint;
        joint.name = "j" + std::to_string(j);
        const bool yaw = j % 2 == 1;
        joint.role = yaw ? JointRole::yaw : JointRole::pitch;
        joint.parent = j;
        joint.child = j + 1;
        joint.pivot = {-j * len - len / 2, 0, width / 2};
        joint.axis = yaw ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
        joint.min_angle = deg_to_rad(-90);
        joint.max_angle = deg_to_rad(90);
        joint.servo = {20, 5.2, 0.3};
        robot.joints.push_back(joint);
    }
    validate(robot);
    Simulation sim(test::world_of(std::move(robot)), test::options_at(dt, iterations, solver));
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    test::drive(sim, "yaw", test::sine(20, 0.5, 120));
    double length = 0;
    sim.run(2);
    Vec3 last = sim.body(0, 0).pose.position;
    for (int cycle = 0; cycle < 10; ++cycle) {
        sim.run(2);
        const Vec3 p = sim.body(0, 0).pose.position;
        length += std::hypot(p.x - last.x, p.y - last.y);
        last = p;
    }
    return 1000 * length / 10;
}

TEST_CASE("block_nncg keeps the anchors' pitch-yaw snake's speed at steps of 10 ms") {
    // issue 14 point 5 (docs/performance.md, section 13, "Motors in the block"): block_nncg at
    // dt 10 ms and 7 iterations, the setting that beats ODE 5x there, within 3 % of its dt 1 ms
    // / 20 on the default floor (measured on the script's start: 60.0 against 58.7 mm per
    // cycle). On a rigid floor pgs at that setting was 15 % off; on the compliant one it is 2.9 %
    const double fine = anchor_snake_speed(ConstraintSolver::block_nncg, 0.001, 20);
    const double block = anchor_snake_speed(ConstraintSolver::block_nncg, 0.01, 7);
    CAPTURE(fine, block);
    CHECK(fine > 50);  // it crawls about 6 cm a cycle
    CHECK(std::abs(block / fine - 1) < 0.03);
}

TEST_CASE(
    "block_nncg takes the band's generic loops on arms hung from a fixed body, with the "
    "profile's bits, and swings them as pgs does") {
    const int steps = 500;  // 0.5 s: the arms swing down from horizontal and up the other side
    const Swing generic = swing(SolverMethod::block_nncg, BlockPath::automatic, steps);
    const Swing profile = swing(SolverMethod::block_nncg, BlockPath::profile, steps);
    const Swing pgs = swing(SolverMethod::pgs, BlockPath::automatic, steps);
    CHECK(names(generic.paths) == "band_generic");
    CHECK(names(profile.paths) == "profile");
    // the same bits through both paths: every link's position and velocities every 10 steps
    REQUIRE(generic.states.size() == profile.states.size());
    size_t same = 0;
    for (size_t k = 0; k < generic.states.size(); ++k) {
        const btVector3 &x = generic.states[k], &y = profile.states[k];
        same += x.x() == y.x() && x.y() == y.y() && x.z() == y.z();
    }
    CHECK(same == generic.states.size());
    // as pgs: as well held together, every link where pgs's is to within 1 mm at every
    // sample, and the arms swung down (measured: 0.16 um apart at most; largest separation
    // 80.85 um with both; the outer links' centres 108 mm below the anchor at the lowest)
    CAPTURE(generic.max_separation, pgs.max_separation, generic.lowest);
    CHECK(generic.max_separation < 1.1 * pgs.max_separation);
    double apart = 0;
    for (size_t k = 0; k < generic.states.size(); k += 3)
        apart = std::max(apart, static_cast<double>((generic.states[k] - pgs.states[k]).length()));
    CAPTURE(apart);
    CHECK(apart < 0.001);
    CHECK(generic.lowest < -0.09);
}

// A compliant floor (FloorSpec's default, or its stiffness and damping): Bullet combines the two
// bodies' contact values into each point (stiffness 1/(1/k0 + 1/k1), damping c0 + c1) and
// setupContactConstraint, which CoulombSolver's rows take, turns them into the row's cfm and erp.
// The robot's bodies add nothing, so the floor's values are the points' own; on a rigid floor
// (FloorSpec::rigid) no point has the flag.
TEST_CASE("every contact point on a compliant floor has the floor's stiffness and damping") {
    for (const bool compliant : {false, true}) {
        CAPTURE(compliant);
        WorldSpec world = test::chain_world(4, Connection::pitch_yaw);
        world.floor.rigid = !compliant;
        // a box on the floor and a robot body touching a static box too
        BoxSpec loose;
        loose.size = {0.05, 0.05, 0.05};
        loose.mass = 0.1;
        loose.pose.position = {0, 0.3, 0.025};
        world.boxes.push_back(loose);
        BoxSpec fixed;
        fixed.size = {0.05, 0.05, 0.05};
        fixed.pose.position = {0.1, 0.026 + 0.025, 0.025};  // against the robot's side
        world.boxes.push_back(fixed);
        PhysicsWorld w(world, kDt, kIterations, ConstraintSolver::pgs);
        for (int k = 0; k < 200; ++k)
            w.step(kDt);
        const btDispatcher& d = *w.bullet_world().getDispatcher();
        int on_floor = 0, elsewhere = 0;
        for (int i = 0; i < d.getNumManifolds(); ++i) {
            const btPersistentManifold& m =
                *const_cast<btDispatcher&>(d).getManifoldByIndexInternal(i);
            const bool floor =
                m.getBody0()->getUserIndex() == -2 || m.getBody1()->getUserIndex() == -2;
            for (int p = 0; p < m.getNumContacts(); ++p) {
                const btManifoldPoint& cp = m.getContactPoint(p);
                const bool flagged =
                    (cp.m_contactPointFlags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) != 0;
                CHECK(flagged == (compliant && floor));
                if (flagged) {  // the default floor's
                    CHECK(cp.m_combinedContactStiffness1 == btScalar(kDefaultFloorStiffness));
                    CHECK(cp.m_combinedContactDamping1 == btScalar(kDefaultFloorDamping));
                }
                ++(floor ? on_floor : elsewhere);
            }
        }
        // the robot's 5 bodies and the loose box lie on the floor on 4 corners each
        CHECK(on_floor >= 20);
        // and a robot body against the static box, whose points stay rigid
        CHECK(elsewhere > 0);
    }
}

// A chain of a thousand hinges or more: K's smallest eigenvalue falls below float's rounding
// of its largest, so with its entries in float K is indefinite, the factor breaks down and the
// solve sends the chain to NaN. From kPreciseBand hinges on the band takes them in double
// (CoulombSolver::band_matrix), and so does the profile from as many rows (profile_matrix).
// every body's state finite (Run::diverged also counts a body 100 m out, as the 160 m chain's)
bool all_finite(const Run& r) {
    for (const BodyState& b : r.states) {
        const Vec3 &p = b.pose.position, &v = b.linear_velocity;
        if (!std::isfinite(p.x + p.y + p.z + v.x + v.y + v.z)) return false;
    }
    return !r.states.empty();
}

TEST_CASE("block_nncg keeps chains whose float factor loses its digits finite") {
    // K's float entries lose most of their digits where a pivot is a small part of its row's
    // diagonal (the rest cancels): there the block takes K in double (kFloatPivot). Before, with
    // float entries, each of these diverged under the standard wave: the thin rods at 0.51 s
    // (smallest pivot 2e-4 of its row's), the heavy links at 0.27 s (0.03)
    struct Case {
        const char* name;
        int links;
        double width, mass;
        Vec3 axis;
        double torque;
    };
    for (const Case& c :
         {Case{"32 rods of 1 m x 1 cm and 1 g, yaw hinges", 32, 0.01, 1e-3, {0, 0, 1}, 0.4},
          Case{"128 links of 1 m x 10 cm and 1 kg, 100 N m servos", 128, 0.1, 1, {0, 1, 0}, 100}}) {
        CAPTURE(c.name);
        WorldSpec world = test::chain_world(2, Connection::pitch_pitch);  // its floor
        // centred: Run::diverged counts a body 100 m out
        world.robots[0].robot =
            test::slender_chain(c.links, {1, c.width, c.width}, c.mass, c.axis, c.torque);
        validate(world.robots[0].robot);
        SineDrive wave;
        for (int j = 0; j < c.links - 1; ++j)
            wave.joints.push_back(j);
        const Run r = run(world, {wave}, 1000, ConstraintSolver::block_nncg);
        CHECK_FALSE(r.diverged);
        CHECK(all_finite(r));
        CHECK(r.max_separation < 1e-3);
    }
}

TEST_CASE("block_nncg keeps a chain of a thousand modules and more finite") {
    SECTION("1000 y1 modules driven by the pitch-pitch gait (NaN at 3 ms in float)") {
        const WorldSpec world = test::chain_world(1000, Connection::pitch_pitch);
        const Run r = run(world, chain_gait(world.robots[0].robot, Connection::pitch_pitch), 20,
                          ConstraintSolver::block_nncg);
        CHECK_FALSE(r.diverged);
        CHECK(r.max_separation < 1e-3);
    }
    SECTION("a URDF chain of 2000 links lying still (NaN at 59 ms in float), and with a branch") {
        const bool branch = GENERATE(false, true);
        CAPTURE(branch);
        std::string urdf = "<robot name='r'>\n";
        const std::string inertial =
            "<inertial><mass value='0.05'/></inertial><collision><origin xyz='0.04 0 0'/>"
            "<geometry><box size='0.08 0.05 0.03'/></geometry></collision>";
        const int links = 2000;
        for (int i = 0; i < links; ++i)
            urdf += "<link name='l" + std::to_string(i) + "'>" + inertial + "</link>\n";
        for (int i = 1; i < links; ++i) {
            urdf += "<joint name='j" + std::to_string(i) +
                    "' type='revolute'><origin xyz='0.08 0 0'/><parent link='l" +
                    std::to_string(i - 1) + "'/><child link='l" + std::to_string(i) +
                    "'/><axis xyz='0 -1 0'/><limit lower='-1.2' upper='1.2' effort='0.5' "
                    "velocity='5'/></joint>\n";
        }
        urdf += "</robot>\n";
        WorldSpec world = test::chain_world(2, Connection::pitch_pitch);  // its floor
        world.robots[0].robot = parse_urdf(urdf, "chain.urdf");
        if (branch) {  // a side link on link 1990 (a body of three hinges: the profile)
            RobotSpec& robot = world.robots[0].robot;
            test::add_branch(robot, 1990, robot.bodies[1990].size, 0.06, 0.03);
            validate(robot);
        }
        const Run r = run(world, {}, 100, ConstraintSolver::block_nncg);
        CHECK(all_finite(r));
        CHECK(r.max_separation < 1e-4);
        CHECK((r.end - r.start).norm() < 1e-4);  // it lies still
    }
}

// friction_disk, the contact's friction impulse (coulomb_solver.h), in btScalar (float in the
// engine's Bullet): Coulomb's law at ordinary scales, and at scales where its squares underflow
// or overflow, or with a slip that is not a number (a diverging world's), an impulse that is
// finite, within the disk and against the slip
TEST_CASE("the friction disk's impulse is Coulomb's, finite and within μN at any scale") {
    using S = btScalar;
    const double tol = std::numeric_limits<S>::epsilon() * 64;
    auto length = [](S a, S b) { return std::hypot(double(a), double(b)); };
    SECTION("ordinary scales: sticking inside the disk, sliding on it against the slip after") {
        // isotropic K = 2 I: the sticking impulse is -w / 2, the sliding one the limit against w
        const auto [s1, s2] = friction_disk(S(2), S(0), S(2), S(3), S(4), S(10));
        CHECK(s1 == Approx(-1.5).epsilon(tol));
        CHECK(s2 == Approx(-2.0).epsilon(tol));
        const auto [d1, d2] = friction_disk(S(2), S(0), S(2), S(3), S(4), S(1));
        CHECK(d1 == Approx(-0.6).epsilon(tol));
        CHECK(d2 == Approx(-0.8).epsilon(tol));
        // anisotropic K: on the disk, and the slip after (w + K l) exactly against l
        const S k11 = 3, k12 = 1, k22 = S(1.5), w1 = 2, w2 = -5, limit = S(0.7);
        const auto [l1, l2] = friction_disk(k11, k12, k22, w1, w2, limit);
        CHECK(length(l1, l2) == Approx(limit).epsilon(tol));
        const double v1 = w1 + k11 * l1 + k12 * l2, v2 = w2 + k12 * l1 + k22 * l2;
        CHECK(std::abs(v1 * l2 - v2 * l1) < tol * std::hypot(v1, v2) * limit);
        CHECK(v1 * l1 + v2 * l2 < 0);
    }
    SECTION("extreme scales: finite, within the disk, against the slip where it has a direction") {
        // at a scale whose squares overflow or underflow, the impulse of an ordinary one,
        // scaled: sticking inside the disk (limit 10) and sliding on it (0.1)
        for (const S scale : {S(1e30), S(1e-30)}) {
            for (const S limit : {S(10), S(0.1)}) {
                CAPTURE(scale, limit);
                const auto [u1, u2] = friction_disk(S(2), S(0.5), S(1), S(1), S(-2), limit);
                const auto [h1, h2] =
                    friction_disk(S(2), S(0.5), S(1), scale, -2 * scale, limit * scale);
                CHECK(h1 == Approx(double(u1) * scale).epsilon(tol));
                CHECK(h2 == Approx(double(u2) * scale).epsilon(tol));
            }
        }
        const S inf = std::numeric_limits<S>::infinity();
        const S nan = std::numeric_limits<S>::quiet_NaN();
        struct Case {
            S w1, w2, limit;
            bool against;  // the slip has a direction: the impulse is the limit against it
        };
        const Case cases[] = {
            {3, 4, S(1e-30), true},  // a normal impulse whose square underflows
            {S(3e-30), S(4e-30), S(1e-35), true},
            {S(3e30), S(4e30), 1, true},  // a slip whose square overflows
            {S(1e30), 0, S(1e29), true},  // both
            {S(3e-25), S(-4e-25), S(1e-36), true},
            {inf, 0, 1, false},  // a diverging world: no direction, no impulse
            {nan, 1, 1, false},
            {nan, nan, S(1e-30), false},
            {0, 0, 1, false},  // no slip: no impulse (sticking)
            {5, 5, 0, false},  // no normal force: no friction
        };
        for (const Case& c : cases) {
            CAPTURE(c.w1, c.w2, c.limit);
            const auto [l1, l2] = friction_disk(S(2), S(0.5), S(1), c.w1, c.w2, c.limit);
            REQUIRE(std::isfinite(l1));
            REQUIRE(std::isfinite(l2));
            CHECK(length(l1, l2) <= c.limit * (1 + tol));
            if (c.against) {
                CHECK(length(l1, l2) == Approx(c.limit).epsilon(tol));
                CHECK(double(l1) * c.w1 + double(l2) * c.w2 < 0);
            } else {
                CHECK(length(l1, l2) == 0);
            }
        }
    }
}
