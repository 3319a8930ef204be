// A body's centre of mass off its shape's centre (BodySpec::center_of_mass): Bullet's body frame
// is then the centre of mass, the shape a compound's child shifted from it
// (engine/src/bullet/physics_world.cpp). These check the outcomes: a push through the shape's
// centre turns the body, a body hanging from a joint settles with its centre of mass under the
// pivot, a box on an edge tips over exactly when its centre of mass passes the edge and rests on
// its face with the heavier side's corners pressing harder, and every pose read back is the
// shape's.
#include <catch2/catch.hpp>

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "bullet/physics_world.h"
#include "engine/sim_support.h"
#include "gaitlab/geometry.h"

using namespace gaitlab;

namespace {

constexpr double kDt = 0.001;
constexpr int kIterations = 20;

// a robot of one box body of `size` and `mass` at `pose`, its centre of mass at `com`
RobotSpec one_box(const Vec3& size, double mass, const Pose& pose, std::optional<Vec3> com) {
    RobotSpec r;
    r.name = "block";
    BodySpec b;
    b.name = "box";
    b.size = size;
    b.mass = mass;
    b.pose = pose;
    b.center_of_mass = com;
    r.bodies.push_back(b);
    validate(r);
    return r;
}

// the world point of `local` (in the frame of a body at `pose`)
Vec3 at(const Pose& pose, const Vec3& local) {
    return pose.position + pose.orientation.rotate(local);
}

}  // namespace

TEST_CASE("a free body pushed through its shape's centre turns when its centre of mass is aside") {
    // no gravity, no floor: a push of 0.1 N·s along y through the shape's centre, whose lever
    // about a centre of mass 5 cm along x turns the body about -z at J × r / I
    const Vec3 size{0.2, 0.1, 0.1};
    const double mass = 1;
    for (const bool offset : {false, true}) {
        CAPTURE(offset);
        WorldSpec world =
            test::world_of(one_box(size, mass, Pose{{0, 0, 1}, {}},
                                   offset ? std::optional<Vec3>(Vec3{0.05, 0, 0}) : std::nullopt));
        world.gravity = {0, 0, 0};
        world.floor.enabled = false;
        PhysicsWorld w(world, kDt, kIterations);
        // poses are the shape's, the centre of mass where the spec puts it
        const BodyState start = w.body(0);
        CHECK(start.pose.position.x == Approx(0).margin(1e-7));
        CHECK(start.pose.position.z == Approx(1).margin(1e-7));
        CHECK(w.position(0).x == Approx(offset ? 0.05 : 0).margin(1e-7));
        btRigidBody& b = w.bullet_body(0);
        const Vec3 lever = start.pose.position - w.position(0);
        b.applyImpulse(btVector3(0, 0.1f, 0),
                       btVector3(btScalar(lever.x), btScalar(lever.y), btScalar(lever.z)));
        for (int i = 0; i < 100; ++i)
            w.step(kDt);
        const BodyState s = w.body(0);
        const double izz = mass * (size.x * size.x + size.y * size.y) / 12;
        CHECK(s.angular_velocity.z == Approx(offset ? -0.1 * 0.05 / izz : 0).margin(1e-6));
        // the centre of mass moves straight on at J / m whatever the lever
        CHECK(w.mass_velocity(0).y == Approx(0.1).epsilon(1e-5));
        // the shape's centre turns about the centre of mass: its reported pose and velocity
        // are the shape's (its centre stays 5 cm from the centre of mass, which moved 1 cm)
        const Vec3 com = w.position(0);
        CHECK((s.pose.position - com).norm() == Approx(offset ? 0.05 : 0).margin(1e-6));
        CHECK(com.y == Approx(0.01).epsilon(1e-3));
        CHECK((at(s.pose, offset ? Vec3{0.05, 0, 0} : Vec3{}) - com).norm() < 1e-6);
    }
}

TEST_CASE("a body hanging from a joint settles with its centre of mass under the pivot") {
    // a heavy base lies on a static pedestal; an arm 30 cm long hangs from a pivot beside the
    // pedestal by a joint whose servo is all but free (1e-9 N·m). Its centre of mass 1.5 cm
    // along its x puts the arm at rest turned by atan(1.5 / 15) = 5.7 degrees about the
    // joint's y axis, the centre of mass under the pivot and the shape's centre 1.5 cm aside
    for (const bool offset : {false, true}) {
        CAPTURE(offset);
        RobotSpec r;
        r.name = "hanger";
        BodySpec base;
        base.name = "base";
        base.size = {0.3, 0.3, 0.1};
        base.mass = 10;
        base.pose.position = {0, 0, 1.05};
        BodySpec arm;
        arm.name = "arm";
        arm.size = {0.04, 0.04, 0.3};
        arm.mass = 1;
        arm.pose.position = {0.25, 0, 0.9};
        if (offset) arm.center_of_mass = Vec3{0.015, 0, 0};
        r.bodies = {base, arm};
        JointSpec j;
        j.name = "hinge";
        j.parent = 0;
        j.child = 1;
        j.pivot = {0.25, 0, 1.05};
        j.axis = {0, 1, 0};
        j.min_angle = -1;
        j.max_angle = 1;
        j.servo.max_torque = 1e-9;
        r.joints = {j};
        validate(r);
        WorldSpec world = test::world_of(r);
        BoxSpec pedestal;
        pedestal.size = {0.4, 0.4, 1.0};
        pedestal.pose.position = {0, 0, 0.5};
        world.boxes.push_back(pedestal);
        PhysicsWorld w(world, kDt, kIterations);
        // the swing dies away (Bullet's damping leaves the rest position alone)
        w.bullet_body(1).setDamping(btScalar(0.5), btScalar(0.9));
        for (int i = 0; i < 8000; ++i)
            w.step(kDt);
        const BodyState s = w.body(1);
        const Vec3 com = w.position(1);
        CAPTURE(com.x, com.z, s.pose.position.x, s.pose.position.z, w.angle(0));
        CHECK(com.x == Approx(0.25).margin(2e-4));
        CHECK(std::abs(s.angular_velocity.y) < 1e-3);
        // the arm turned about +y by the angle (its centre of mass, at local x, swung back
        // under the pivot), its shape's centre to -x
        const double turn = std::atan2(0.015, 0.15);
        CHECK(s.pose.position.x ==
              Approx(offset ? 0.25 - 0.15 * std::sin(turn) : 0.25).margin(5e-4));
        CHECK(w.angle(0) == Approx(offset ? turn : 0).margin(2e-3));
        // the pivot stays where it was, read from the shape's pose: the arm's top centre
        CHECK((at(s.pose, {0, 0, 0.15}) - Vec3{0.25, 0, 1.05}).norm() < 5e-4);
    }
}

TEST_CASE("a box on an edge tips over exactly when its centre of mass passes the edge") {
    // a cube of 20 cm tilted by 20 degrees about y stands on its lower bottom edge (at local
    // x = +10 cm, z = -10 cm). Its centre of mass at local x = c lies beyond the edge's
    // vertical line when c > 0.1 (1 - tan 20°) = 6.36 cm: then it tips over onto its +x face,
    // otherwise it falls back onto its bottom face
    const double tilt = deg_to_rad(20);
    const double threshold = 0.1 * (1 - std::tan(tilt));
    struct Case {
        std::optional<double> c;
        bool tips;
    };
    const Case cases[] = {{std::nullopt, false},
                          {0.0, false},
                          {threshold - 0.006, false},
                          {threshold + 0.006, true},
                          {0.1, true}};
    for (const Case& k : cases) {
        CAPTURE(k.c.value_or(-1), threshold);
        const Quat q = Quat::from_axis_angle({0, 1, 0}, tilt);
        Pose pose;
        pose.orientation = q;
        // the edge's corners just above the floor
        pose.position = {0, 0, 0.1 * std::sin(tilt) + 0.1 * std::cos(tilt) + 1e-4};
        WorldSpec world = test::world_of(one_box(
            {0.2, 0.2, 0.2}, 1, pose, k.c ? std::optional<Vec3>(Vec3{*k.c, 0, 0}) : std::nullopt));
        Simulation sim(world);
        sim.run(2.0);
        const Pose p = sim.body(0, 0).pose;
        // the body's z axis: upright when it fell back, along +x when it tipped over (+x down)
        const Vec3 z = p.orientation.rotate({0, 0, 1});
        CAPTURE(z.x, z.z, p.position.z);
        if (k.tips) {
            CHECK(z.x == Approx(1).margin(0.01));
        } else {
            CHECK(z.z == Approx(1).margin(0.01));
        }
        // either way it rests on a face: its shape's centre half a side above the floor
        CHECK(p.position.z == Approx(0.1).margin(0.002));
    }
}

TEST_CASE("a box resting on its face presses harder at the corners on its centre of mass's side") {
    // the box's 4 bottom corners carry its weight; its centre of mass 5 cm towards +x of a 20 cm
    // box puts (1/2 + 5/20) of it on the two +x corners, 3/4, and 1/4 on the -x ones: the
    // points are at the shape's true corners, not shifted with the centre of mass
    const double g = 9.81, mass = 2;
    for (const bool offset : {false, true}) {
        CAPTURE(offset);
        Pose pose;
        pose.position = {0, 0, 0.05 + 1e-4};
        WorldSpec world =
            test::world_of(one_box({0.2, 0.1, 0.1}, mass, pose,
                                   offset ? std::optional<Vec3>(Vec3{0.05, 0, 0}) : std::nullopt));
        world.floor.rigid = true;
        Simulation sim(world);
        sim.run(1.0);
        std::vector<ContactPoint> points;
        sim.contacts(points);
        REQUIRE(points.size() == 4);
        double plus = 0, minus = 0;
        for (const ContactPoint& p : points) {
            CAPTURE(p.position.x, p.position.y, p.position.z);
            CHECK(std::abs(std::abs(p.position.x) - 0.1) < 1e-3);
            CHECK(std::abs(std::abs(p.position.y) - 0.05) < 1e-3);
            (p.position.x > 0 ? plus : minus) += p.force;
        }
        CAPTURE(plus, minus);
        const double weight = mass * g;
        CHECK(plus + minus == Approx(weight).epsilon(0.01));
        CHECK(plus == Approx(weight * (offset ? 0.75 : 0.5)).epsilon(0.02));
        CHECK(minus == Approx(weight * (offset ? 0.25 : 0.5)).epsilon(0.04));
        // it rests where it was put: shape's centre at half its height above the floor
        CHECK(sim.body(0, 0).pose.position.z == Approx(0.05).margin(1e-3));
    }
}

TEST_CASE("a box with its centre of mass aside rests on a heightfield at its true corners") {
    // the engine's box-heightfield collider meets the compound's child box as it meets a plain
    // box: on a flat field 5 cm high, the box rests with its shape's bottom on the field, its
    // heavier side pressing harder
    const double g = 9.81, mass = 2;
    Pose pose;
    pose.position = {0, 0, 0.05 + 0.05 + 1e-4};
    WorldSpec world = test::world_of(one_box({0.2, 0.1, 0.1}, mass, pose, Vec3{0.05, 0, 0}));
    world.floor.enabled = false;
    HeightfieldSpec field;
    field.length = 2;
    field.width = 2;
    field.samples_x = 5;
    field.samples_y = 5;
    field.heights.assign(25, 0.05);
    world.heightfields.push_back(field);
    Simulation sim(world);
    sim.run(1.0);
    const Pose p = sim.body(0, 0).pose;
    CHECK(p.position.z == Approx(0.1).margin(1e-3));
    CHECK(p.orientation.rotate({0, 0, 1}).z == Approx(1).margin(1e-4));
    std::vector<ContactPoint> points;
    sim.contacts(points);
    REQUIRE(points.size() == 4);
    double plus = 0, minus = 0;
    for (const ContactPoint& c : points) {
        CAPTURE(c.position.x, c.position.y, c.position.z);
        CHECK(std::abs(std::abs(c.position.x) - 0.1) < 1e-3);
        CHECK(c.position.z == Approx(0.05).margin(1e-3));
        (c.position.x > 0 ? plus : minus) += c.force;
    }
    CAPTURE(plus, minus);
    CHECK(plus == Approx(0.75 * mass * g).epsilon(0.03));
    CHECK(minus == Approx(0.25 * mass * g).epsilon(0.06));
}

TEST_CASE("a robot with centres of mass aside clones to the bit and reads shape poses") {
    // a chain whose segments carry their centres of mass towards the head, driven by a sine:
    // a clone made mid-run goes on exactly as its original; positions read back are the
    // shapes' (at rest: the spec's), the robot's position its true centre of mass
    RobotSpec robot =
        make_chain(ChainSpec{"heavy_head", 4, Connection::pitch_pitch, default_module_def()});
    robot.chain.reset();
    for (BodySpec& b : robot.bodies)
        b.center_of_mass = Vec3{b.size.x / 4, 0, -b.size.z / 4};
    validate(robot);
    Simulation sim(test::world_of(robot));
    test::drive(sim, "all", test::sine(30, 0.5, 90));
    for (size_t b = 0; b < robot.bodies.size(); ++b) {
        CAPTURE(b);
        const Vec3 d =
            sim.body(0, static_cast<int>(b)).pose.position - robot.bodies[b].pose.position;
        CHECK(d.norm() < 1e-6);
    }
    Vec3 com;
    double total = 0;
    for (const BodySpec& b : robot.bodies) {
        com += at(b.pose, *b.center_of_mass) * b.mass;
        total += b.mass;
    }
    com = com * (1 / total);
    CHECK((sim.robot_position(0) - com).norm() < 1e-6);
    sim.run(1.0);
    auto copy = sim.clone();
    sim.run(1.0);
    copy->run(1.0);
    for (size_t b = 0; b < robot.bodies.size(); ++b) {
        const BodyState x = sim.body(0, static_cast<int>(b)),
                        y = copy->body(0, static_cast<int>(b));
        CHECK(x.pose.position == y.pose.position);
        CHECK(x.pose.orientation == y.pose.orientation);
        CHECK(x.linear_velocity == y.linear_velocity);
    }
    CHECK(sim.robot_position(0) == copy->robot_position(0));
}

TEST_CASE(
    "a centre of mass given at the shape's centre moves the body as none given, bit for bit") {
    // com = {0, 0, 0} says what the default says: the body keeps its plain shape, so a gait
    // on the floor, pushing boxes about, follows the same trajectory to the last bit
    const auto run = [](bool given) {
        RobotSpec robot =
            make_chain(ChainSpec{"snake", 4, Connection::pitch_yaw, default_module_def()});
        robot.chain.reset();
        for (BodySpec& b : robot.bodies)
            b.center_of_mass = given ? std::optional<Vec3>(Vec3{0, 0, 0}) : std::nullopt;
        validate(robot);
        WorldSpec world = test::world_of(robot);
        // loose boxes on both sides of the chain, which it pushes: contacts between
        // bodies as well as with the floor
        for (const double y : {0.048, -0.048}) {
            for (const double x : {-0.2, -0.1, 0.0, 0.1, 0.2}) {
                BoxSpec box;
                box.size = {0.04, 0.04, 0.04};
                box.pose.position = {x, y, 0.02};
                box.mass = 0.02;
                world.boxes.push_back(box);
            }
        }
        Simulation sim(world);
        test::drive(sim, "all", test::sine(40, 0.5, 90));
        const Vec3 start = sim.robot_position(0);
        sim.run(2.0);
        std::vector<BodyState> out;
        for (size_t b = 0; b < robot.bodies.size(); ++b)
            out.push_back(sim.body(0, static_cast<int>(b)));
        // and the loose boxes' states
        for (int k = 0; k < 10; ++k)
            out.push_back(sim.object(k));
        return std::make_pair(out, (sim.robot_position(0) - start).norm());
    };
    const auto [plain, moved] = run(false);
    const auto [zero, moved_zero] = run(true);
    REQUIRE(plain.size() == zero.size());
    // the gait moved the robot, so equal states are not two robots lying still
    CHECK(moved > 0.005);
    CHECK(moved == moved_zero);
    const size_t bodies = plain.size() - 10;
    double pushed = 0;
    for (size_t k = 0; k < 10; ++k)
        pushed = std::max(
            pushed, (plain[bodies + k].pose.position -
                     Vec3{-0.2 + 0.1 * static_cast<double>(k % 5), k < 5 ? 0.048 : -0.048, 0.02})
                        .norm());
    CAPTURE(pushed);
    CHECK(pushed > 0.001);
    for (size_t b = 0; b < plain.size(); ++b) {
        CAPTURE(b);
        CHECK(plain[b].pose.position == zero[b].pose.position);
        CHECK(plain[b].pose.orientation == zero[b].pose.orientation);
        CHECK(plain[b].linear_velocity == zero[b].linear_velocity);
    }
}
