// Tests for engine/src/sim/sensing.cpp (and the Bullet probes it uses, engine/src/bullet/
// sensor_probes.cpp) through the Simulation API: each kind of sensor reads what the physics
// does, switches stop and resume readings, and sensing never changes a trajectory.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "engine/sim_support.h"
#include "gaitlab/controllers/offset.h"
#include "gaitlab/error.h"
#include "gaitlab/simulation.h"

using namespace gaitlab;
using Catch::Matchers::Equals;

namespace {

SensorSpec imu(int module, ModuleHalf half = ModuleHalf::head) {
    SensorSpec s;
    s.kind = SensorKind::imu;
    s.module = module;
    s.half = half;
    return s;
}

SensorSpec contact(int module) {
    SensorSpec s;
    s.kind = SensorKind::contact;
    s.module = module;
    return s;
}

SensorSpec range(int module, Vec3 direction, double max_range = 2.0) {
    SensorSpec s;
    s.kind = SensorKind::range;
    s.module = module;
    s.direction = direction;
    s.max_range = max_range;
    return s;
}

SensorSpec joint_sensor(int joint) {
    SensorSpec s;
    s.kind = SensorKind::joint;
    s.joint = joint;
    return s;
}

SensorSpec position_sensor() {
    SensorSpec s;
    s.kind = SensorKind::position;
    return s;
}

// the value of channel `name` of the sensor called `sensor` of robot 0
double value(const Simulation& sim, const char* sensor, const char* name) {
    const int i = sim.find_sensor(0, sensor);
    REQUIRE(i >= 0);
    const int c = find_sensor_channel(sim.sensor(i).kind, name);
    REQUIRE(c >= 0);
    return sim.sensor_values(i)[static_cast<size_t>(c)];
}

double deg(const Simulation& sim, const char* sensor, const char* name) {
    return rad_to_deg(value(sim, sensor, name));
}

// holds joint j (0-based) of robot 0 at `angle_deg` with an offset controller
void hold(Simulation& sim, int j, double angle_deg) {
    auto c = std::make_shared<controllers::Offset>();
    c->set_param("angle", angle_deg);
    Drive d;
    d.joints = {j};
    d.controller = c;
    sim.add_drive(0, std::move(d));
}

}  // namespace

TEST_CASE("a joint sensor reads the joint's angle, velocity and torque") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    w.robots[0].robot.sensors = {joint_sensor(1), joint_sensor(3)};
    Simulation sim(w);
    test::drive_pitch_pitch_gait(sim, 120);
    for (int k = 0; k < 5; ++k) {
        sim.run(0.37);
        for (int j : {1, 3}) {
            const std::vector<double>& v =
                sim.sensor_values(sim.find_sensor(0, j == 1 ? "joint2" : "joint4"));
            const JointState s = sim.joint(0, j);
            CHECK(v[0] == s.angle);
            CHECK(v[1] == s.velocity);
            CHECK(v[2] == s.torque);
        }
    }
    CHECK(std::abs(sim.joint(0, 1).angle) > 0.05);  // the gait moves it
}

TEST_CASE("an IMU on a resting robot reads no tilt, no rotation and gravity upward") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    w.robots[0].robot.sensors = {imu(0, ModuleHalf::tail), imu(2)};
    Simulation sim(w);
    // at build: the state at rest, acceleration taken as zero
    CHECK(value(sim, "imu3", "az") == Approx(9.81));
    sim.run(0.5);
    for (const char* name : {"imu1", "imu3"}) {
        CHECK(std::abs(deg(sim, name, "roll")) < 0.01);
        CHECK(std::abs(deg(sim, name, "pitch")) < 0.01);
        CHECK(std::abs(deg(sim, name, "yaw")) < 0.01);
        CHECK(value(sim, name, "qw") == Approx(1).margin(1e-5));
        for (const char* w_ : {"wx", "wy", "wz"})
            CHECK(std::abs(deg(sim, name, w_)) < 0.05);
        // an accelerometer measures specific force: +g upward at rest
        CHECK(std::abs(value(sim, name, "ax")) < 0.01);
        CHECK(std::abs(value(sim, name, "ay")) < 0.01);
        CHECK(value(sim, name, "az") == Approx(9.81).margin(0.01));
    }
}

TEST_CASE("an IMU in free fall reads no specific force, placement turns its yaw") {
    WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    w.floor.enabled = false;
    w.robots[0].pose.orientation = Quat::from_axis_angle({0, 0, 1}, deg_to_rad(90));
    w.robots[0].robot.sensors = {imu(1)};
    Simulation sim(w);
    sim.run(0.2);
    CHECK(deg(sim, "imu2", "yaw") == Approx(90).margin(1e-4));
    // (Bullet computes in single precision: velocity differences over 1 ms are good to ~1e-3)
    CHECK(std::abs(value(sim, "imu2", "ax")) < 0.01);
    CHECK(std::abs(value(sim, "imu2", "ay")) < 0.01);
    CHECK(std::abs(value(sim, "imu2", "az")) < 0.01);
    // the body falls at g: its velocity after 0.2 s
    CHECK(sim.body(0, 2).linear_velocity.z == Approx(-9.81 * 0.2).epsilon(1e-4));
}

TEST_CASE("an IMU on a module turned by a held joint reads that angle") {
    SECTION("pitch: the head half of module 4 lifted by joint 4") {
        WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
        w.robots[0].robot.sensors = {imu(3), imu(3, ModuleHalf::tail), imu(0, ModuleHalf::tail)};
        w.robots[0].robot.sensors[1].name = "imu4_tail";
        Simulation sim(w);
        hold(sim, 3, 30);
        sim.run(1.5);
        const double angle = rad_to_deg(sim.joint(0, 3).angle);
        CHECK(angle == Approx(30).margin(0.5));
        CHECK(deg(sim, "imu4", "pitch") == Approx(angle).margin(0.2));
        CHECK(std::abs(deg(sim, "imu4_tail", "pitch")) < 0.2);
        CHECK(std::abs(deg(sim, "imu1", "pitch")) < 0.2);
        CHECK(std::abs(deg(sim, "imu4", "roll")) < 0.1);
        // still: gravity seen tilted in the module's frame
        CHECK(value(sim, "imu4", "ax") == Approx(9.81 * std::sin(deg_to_rad(angle))).margin(0.05));
        CHECK(value(sim, "imu4", "az") == Approx(9.81 * std::cos(deg_to_rad(angle))).margin(0.05));
    }
    SECTION("yaw: the head half of module 3 turned by joint 3") {
        WorldSpec w = test::chain_world(3, Connection::yaw_yaw);
        w.robots[0].robot.sensors = {imu(2)};
        Simulation sim(w);
        hold(sim, 2, -45);
        sim.run(1.5);
        const double angle = rad_to_deg(sim.joint(0, 2).angle);
        CHECK(angle == Approx(-45).margin(0.5));
        // the rest of the chain turns a little the other way: the reading is the head's heading
        const Quat q = sim.body(0, 3).pose.orientation;
        const Vec3 x = q.rotate({1, 0, 0});
        CHECK(deg(sim, "imu3", "yaw") == Approx(rad_to_deg(std::atan2(x.y, x.x))).margin(1e-9));
        CHECK(deg(sim, "imu3", "yaw") < -30);
        CHECK(std::abs(deg(sim, "imu3", "pitch")) < 0.1);
    }
}

TEST_CASE("contact sensors are on for modules on the floor and off for a lifted module") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    for (int m = 0; m < 4; ++m)
        w.robots[0].robot.sensors.push_back(contact(m));
    Simulation sim(w);
    sim.run(0.3);
    double total = 0;
    for (const char* name : {"contact1", "contact2", "contact3", "contact4"}) {
        CHECK(value(sim, name, "contact") == 1);
        total += value(sim, name, "force");
    }
    // at rest the floor carries the robot's weight
    CHECK(total == Approx(0.2 * 9.81).epsilon(0.02));

    // joint 3 lifts the segment after it and the head: all of module 4 leaves the floor, and
    // module 3 keeps its tail half on it
    hold(sim, 2, 40);
    sim.run(1.5);
    CHECK(value(sim, "contact1", "contact") == 1);
    CHECK(value(sim, "contact2", "contact") == 1);
    CHECK(value(sim, "contact3", "contact") == 1);
    CHECK(value(sim, "contact4", "contact") == 0);
    CHECK(value(sim, "contact4", "force") == 0);
    total = 0;
    for (const char* name : {"contact1", "contact2", "contact3"})
        total += value(sim, name, "force");
    CHECK(total == Approx(0.2 * 9.81).epsilon(0.02));
}

TEST_CASE("a range sensor reads its height above the floor and the distance to a wall") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    BoxSpec wall;
    wall.size = {0.1, 1, 0.3};
    wall.pose.position = {1.0, 0, 0.15};
    w.boxes.push_back(wall);
    auto& sensors = w.robots[0].robot.sensors;
    sensors = {range(2, {0, 0, -1}), range(3, {1, 0, 0}), range(3, {1, 0, 0}, 0.5),
               range(0, {-1, 0, 0}), range(2, {0, 0, 1})};
    sensors[0].name = "down";
    sensors[1].name = "ahead";
    sensors[2].name = "short";
    sensors[3].name = "behind";
    sensors[3].half = ModuleHalf::tail;
    sensors[4].name = "up";
    Simulation sim(w);
    // from the centre of the head half (x = 0.270 m) to the wall's face at x = 0.95 m; the
    // ray passes through nothing of its own robot. At every tick of the robot lying still: a
    // ray cast that stops short by up to 2 mm depending on the last bits of its origin (Bullet's
    // default approximate ray-convex test) fails at some of them
    for (int tick = 0; tick < 300; ++tick) {
        sim.step(1);
        CAPTURE(tick);
        REQUIRE(value(sim, "ahead", "distance") == Approx(0.95 - 0.270).margin(1e-4));
    }
    // from the centre of module 3's head half, 26 mm above the floor
    CHECK(value(sim, "down", "distance") == Approx(0.026).margin(2e-4));
    CHECK(value(sim, "down", "hit") == 1);
    CHECK(value(sim, "ahead", "hit") == 1);
    // beyond its maximum range: no hit, the reading is the maximum
    CHECK(value(sim, "short", "distance") == 0.5);
    CHECK(value(sim, "short", "hit") == 0);
    // from the tail looking back along -x: nothing there; straight up: nothing either
    CHECK(value(sim, "behind", "hit") == 0);
    CHECK(value(sim, "up", "hit") == 0);
    CHECK(value(sim, "up", "distance") == 2.0);

    // the ray turns with the module: module 3's head half pitched up by joint 3 sees the floor
    // along a slanted ray, from higher up
    hold(sim, 2, 30);
    sim.run(1.5);
    const BodyState b = sim.body(0, 3);
    const Vec3 down = b.pose.orientation.rotate({0, 0, -1});
    CHECK(-down.z == Approx(std::cos(deg_to_rad(30))).margin(0.01));
    CHECK(value(sim, "down", "distance") == Approx(b.pose.position.z / -down.z).margin(1e-4));
    CHECK(value(sim, "down", "distance") > 0.04);
}

namespace {

// a 2-module chain lying on the floor with one range sensor, "ray", on the tail half of its
// module 1: the ray starts at that half's centre, kRayOrigin
constexpr Vec3 kRayOrigin{0.018, 0, 0.026};
WorldSpec ray_world(Vec3 direction) {
    WorldSpec w = test::chain_world(2, Connection::pitch_pitch);
    SensorSpec s = range(0, direction);
    s.name = "ray";
    s.half = ModuleHalf::tail;
    w.robots[0].robot.sensors = {s};
    return w;
}

// the reading of "ray" when the simulation is built (before any step: robots and objects stand
// exactly where `w` puts them)
struct RayReading {
    double distance, hit;
};
RayReading ray_reading(const WorldSpec& w) {
    Simulation sim(w);
    return {value(sim, "ray", "distance"), value(sim, "ray", "hit")};
}

// a second chain, robot 1, moved by `at`
PlacedRobot other_robot(Vec3 at) {
    ChainSpec chain;
    chain.name = "other";
    chain.modules = 2;
    PlacedRobot placed;
    placed.robot = make_chain(chain);
    placed.pose.position = at;
    return placed;
}

}  // namespace

TEST_CASE("a range sensor's direction may be of any length: tiny and huge ones read as unit ones") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    auto& sensors = w.robots[0].robot.sensors;
    // 45 degrees down; the huge one's norm overflows to infinity, the tiny one's underflows to 0
    sensors = {range(2, {1, 0, -1}), range(2, {1e300, 0, -1e300}), range(2, {1e-300, 0, -1e-300})};
    sensors[0].name = "unit";
    sensors[1].name = "huge";
    sensors[2].name = "tiny";
    Simulation sim(w);
    sim.step(1);
    REQUIRE(value(sim, "unit", "hit") == 1);
    for (const char* name : {"huge", "tiny"}) {
        CAPTURE(name);
        CHECK(value(sim, name, "hit") == 1);
        CHECK(value(sim, name, "distance") == value(sim, "unit", "distance"));
    }
}

TEST_CASE("a range sensor whose ray starts inside a solid reads a hit at distance 0") {
    // each solid encloses kRayOrigin; the ray reads the same whichever way it points: up, out
    // of the solid's side, down, or along the robot
    const Vec3 direction = GENERATE(Vec3{0, 0, 1}, Vec3{0, 1, 0}, Vec3{0, 0, -1}, Vec3{1, 0, 0});
    CAPTURE(direction.x, direction.y, direction.z);
    WorldSpec w = ray_world(direction);
    SECTION("a static box") {
        BoxSpec box;
        box.size = {0.02, 0.02, 0.02};
        box.pose.position = kRayOrigin;
        w.boxes.push_back(box);
    }
    SECTION("a box that moves") {
        BoxSpec box;
        box.size = {0.02, 0.02, 0.02};
        box.pose.position = kRayOrigin + Vec3{0.005, -0.004, 0.003};
        box.mass = 0.1;
        w.boxes.push_back(box);
    }
    SECTION("an upright cylinder") {
        CylinderSpec c;
        c.radius = 0.01;
        c.length = 0.02;
        c.position = kRayOrigin + Vec3{0.007, 0.007, 0};  // 9.9 mm off its axis
        w.cylinders.push_back(c);
    }
    SECTION("a lying cylinder that moves") {
        CylinderSpec c;
        c.radius = 0.01;
        c.length = 0.02;
        c.lying = true;
        c.yaw = deg_to_rad(90);
        c.position = kRayOrigin + Vec3{-0.007, 0, 0.007};
        c.mass = 0.1;
        w.cylinders.push_back(c);
    }
    SECTION("a ramp (a convex hull)") {
        RampSpec r;
        r.slope = deg_to_rad(45);
        r.length = 0.2;
        r.position = {-0.1, 0, 0};  // 0.118 m high over kRayOrigin
        w.ramps.push_back(r);
    }
    SECTION("a static box among others (children of one compound shape)") {
        for (double x : {-0.3, 0.018, 0.3}) {
            BoxSpec box;
            box.size = {0.02, 0.02, 0.02};
            box.pose.position = {x, 0, 0.026};
            w.boxes.push_back(box);
        }
    }
    SECTION("a heightfield, under its surface") {
        HeightfieldSpec h;
        h.samples_x = h.samples_y = 3;
        h.heights = {0.02, 0.05, 0.02, 0.05, 0.08, 0.05, 0.02, 0.05, 0.02};
        w.heightfields.push_back(h);  // its surface about 5 cm above kRayOrigin
    }
    SECTION("the floor, under it") {
        w.robots[0].pose.position.z = -0.0265;
    }
    SECTION("another robot's body") {
        w.robots.push_back(other_robot({0.01, 0.02, 0}));
    }
    const RayReading r = ray_reading(w);
    CHECK(r.hit == 1);
    CHECK(r.distance == 0);
}

TEST_CASE("a range sensor on a module sunk into a soft floor reads a hit at 0 once under it") {
    // a floor so soft (1 N/m per contact point) that the modules sink into it
    WorldSpec w = ray_world({0, 0, -1});
    w.floor.stiffness = 1;
    w.floor.damping = 1;
    Simulation sim(w);
    CHECK(value(sim, "ray", "distance") == Approx(0.026).margin(1e-5));
    bool under = false;
    for (int tick = 0; tick < 3000 && !under; ++tick) {
        sim.step(1);
        const double z = sim.body(0, 0).pose.position.z;
        CAPTURE(tick, z);
        if (z > 0.0005) {
            // above the surface: its height, as before
            REQUIRE(value(sim, "ray", "hit") == 1);
            REQUIRE(value(sim, "ray", "distance") == Approx(z).margin(2e-4));
        } else if (z < -0.0005) {
            under = true;
            CHECK(value(sim, "ray", "hit") == 1);
            CHECK(value(sim, "ray", "distance") == 0);
        }
    }
    CAPTURE(sim.body(0, 0).pose.position.z);
    CHECK(under);
}

TEST_CASE("a range sensor just outside a solid reads the distance to it") {
    SECTION("1 mm under a box") {
        WorldSpec w = ray_world({0, 0, 1});
        BoxSpec box;
        box.size = {0.02, 0.02, 0.02};
        box.pose.position = kRayOrigin + Vec3{0, 0, 0.011};
        w.boxes.push_back(box);
        CHECK(ray_reading(w).distance == Approx(0.001).margin(1e-5));
        // the same box a little farther, on a slanted ray
        w.robots[0].robot.sensors[0].direction = {1, 0, 1};
        w.boxes[0].pose.position = kRayOrigin + Vec3{0.008, 0, 0.018};
        CHECK(ray_reading(w).distance == Approx(0.008 * std::sqrt(2.0)).margin(1e-5));
    }
    SECTION("1 mm beside a cylinder") {
        WorldSpec w = ray_world({0, 1, 0});
        CylinderSpec c;
        c.radius = 0.01;
        c.length = 0.02;
        c.position = kRayOrigin + Vec3{0, 0.011, 0};
        w.cylinders.push_back(c);
        CHECK(ray_reading(w).distance == Approx(0.001).margin(1e-5));
    }
    SECTION("1 mm above a heightfield and the floor") {
        HeightfieldSpec h;
        h.samples_x = h.samples_y = 2;
        h.heights = {0.025, 0.025, 0.025, 0.025};
        WorldSpec w = ray_world({0, 0, -1});
        w.heightfields.push_back(h);
        CHECK(ray_reading(w).distance == Approx(0.001).margin(1e-5));
        w.heightfields.clear();
        w.robots[0].pose.position.z = -0.025;
        CHECK(ray_reading(w).distance == Approx(0.001).margin(1e-5));
    }
    SECTION("beside a heightfield, 1 mm off its grid") {
        HeightfieldSpec h;
        h.samples_x = h.samples_y = 2;
        h.heights = {0.05, 0.05, 0.05, 0.05};
        h.length = h.width = 0.1;
        h.position = {0.018 + 0.051, 0, 0};
        WorldSpec w = ray_world({0, 0, -1});
        w.heightfields.push_back(h);
        CHECK(ray_reading(w).distance == Approx(0.026).margin(1e-5));  // the floor
    }
    SECTION("1 mm from another robot's body") {
        WorldSpec w = ray_world({0, 1, 0});
        w.robots.push_back(other_robot({0, 0.027, 0}));  // its side at y = 0.001
        CHECK(ray_reading(w).distance == Approx(0.001).margin(1e-5));
    }
}

TEST_CASE("a range sensor's own robot is transparent to it, with self-collision too") {
    // the ray starts inside the robot's own body, and along +x crosses the rest of it
    const bool self_collision = GENERATE(false, true);
    WorldSpec w = ray_world({1, 0, 0});
    w.robots[0].robot.self_collision = self_collision;
    RayReading r = ray_reading(w);
    CHECK(r.hit == 0);
    CHECK(r.distance == 2.0);
    BoxSpec wall;
    wall.size = {0.1, 1, 0.3};
    wall.pose.position = {0.5, 0, 0.15};
    w.boxes.push_back(wall);
    r = ray_reading(w);
    CHECK(r.hit == 1);
    CHECK(r.distance == Approx(0.45 - 0.018).margin(1e-5));
}

TEST_CASE("a position sensor reads the centre of mass and its velocity") {
    WorldSpec w = test::chain_world(6, Connection::pitch_pitch);
    w.robots[0].robot.sensors = {position_sensor()};
    Simulation sim(w);
    test::drive_pitch_pitch_gait(sim, 120);
    const int i = sim.find_sensor(0, "position");
    for (int k = 0; k < 4; ++k) {
        sim.run(0.53);
        const std::vector<double>& v = sim.sensor_values(i);
        const Vec3 x = sim.robot_position(0), u = sim.robot_velocity(0);
        CHECK(v[0] == Approx(x.x).margin(1e-12));
        CHECK(v[1] == Approx(x.y).margin(1e-12));
        CHECK(v[2] == Approx(x.z).margin(1e-12));
        CHECK(v[3] == Approx(u.x).margin(1e-12));
        CHECK(v[4] == Approx(u.y).margin(1e-12));
        CHECK(v[5] == Approx(u.z).margin(1e-12));
    }
    CHECK(std::abs(sim.sensor_values(i)[3]) > 1e-4);  // it moves
}

TEST_CASE("a switched-off sensor keeps its last reading, switched on it reads again") {
    WorldSpec w = test::chain_world(4, Connection::pitch_pitch);
    // each switched sensor has an always-on twin on the same joint or module
    w.robots[0].robot.sensors = {joint_sensor(2), joint_sensor(2), contact(3), contact(3)};
    w.robots[0].robot.sensors[1].name = "twin_joint";
    w.robots[0].robot.sensors[2].enabled = false;
    w.robots[0].robot.sensors[3].name = "twin_contact";
    Simulation sim(w);
    test::drive_pitch_pitch_gait(sim, 120);
    const int j = sim.find_sensor(0, "joint3"), tj = sim.find_sensor(0, "twin_joint");
    const int c = sim.find_sensor(0, "contact4"), tc = sim.find_sensor(0, "twin_contact");
    CHECK(sim.sensor_enabled(j));
    CHECK_FALSE(sim.sensor_enabled(c));
    // off from the start: never read
    CHECK(sim.sensor_values(c) == std::vector<double>{0, 0});

    sim.run(0.5);
    CHECK(sim.sensor_values(j) == sim.sensor_values(tj));
    CHECK(sim.sensor_values(c) == std::vector<double>{0, 0});
    sim.set_sensor_enabled(j, false);
    const std::vector<double> stale = sim.sensor_values(j);
    sim.run(0.5);
    CHECK(sim.sensor_values(j) == stale);
    CHECK(sim.sensor_values(tj) != stale);
    CHECK_FALSE(sim.world().robots[0].robot.sensors[0].enabled);

    // on again: a reading at once, then every tick
    sim.set_sensor_enabled(j, true);
    sim.set_sensor_enabled(c, true);
    CHECK(sim.sensor_values(j) == sim.sensor_values(tj));
    CHECK(sim.sensor_values(c) == sim.sensor_values(tc));
    for (int k = 0; k < 5; ++k) {
        sim.run(0.25);
        CHECK(sim.sensor_values(j) == sim.sensor_values(tj));
        CHECK(sim.sensor_values(c) == sim.sensor_values(tc));
    }
    CHECK(sim.world().robots[0].robot.sensors[2].enabled);

    // reset keeps the switches and reads the rebuilt state
    sim.set_sensor_enabled(j, false);
    const std::vector<double> before_reset = sim.sensor_values(j);
    sim.reset();
    CHECK_FALSE(sim.sensor_enabled(j));
    CHECK(sim.sensor_values(j) == before_reset);
    CHECK(sim.sensor_values(tj)[0] == sim.joint(0, 2).angle);
    // contacts come from the last step's collision detection: none before the first step
    CHECK(sim.sensor_values(c)[0] == 0);
    sim.step(1);
    CHECK(sim.sensor_values(c)[0] == 1);
}

TEST_CASE("sensors can be added while the simulation runs") {
    Simulation sim(test::chain_world(3, Connection::pitch_pitch));
    CHECK(sim.sensor_count() == 0);
    sim.run(0.2);
    const int i = sim.add_sensor(0, imu(2));
    CHECK(i == 0);
    CHECK(sim.sensor(i).name == "imu3");
    CHECK(sim.sensor_robot(i) == 0);
    CHECK(sim.sensor_index(0, 0) == i);
    CHECK(sim.sensor_values(i)[12] == Approx(9.81).margin(0.01));
    CHECK(sim.world().robots[0].robot.sensors.size() == 1);
    REQUIRE_THROWS_WITH(sim.add_sensor(0, imu(2)),
                        Equals("robot 'snake' already has a sensor named 'imu3' (give this one "
                               "another name)"));
    REQUIRE_THROWS_WITH(sim.add_sensor(0, imu(3)),
                        Equals("robot 'snake' has no module 4 (it has modules 1 to 3)"));
    REQUIRE_THROWS_WITH(sim.sensor_values(1), Equals("sensor index 1 out of range [0, 1)"));
    REQUIRE_THROWS_WITH(sim.add_sensor(1, imu(0)), Equals("robot index 1 out of range [0, 1)"));
    CHECK(sim.find_sensor(0, "imu9") == -1);
    CHECK(sim.sensor_channels(i).size() == 13);
}

TEST_CASE("sensing never changes the trajectory") {
    auto trajectory = [](bool with_sensors, bool enabled) {
        WorldSpec w = test::chain_world(6, Connection::pitch_yaw);
        BoxSpec box;
        box.pose.position = {-0.3, 0.05, 0.05};
        w.boxes.push_back(box);
        if (with_sensors) {
            auto& s = w.robots[0].robot.sensors;
            s.push_back(position_sensor());
            for (int m = 0; m < 6; ++m) {
                s.push_back(joint_sensor(m));
                s.push_back(imu(m));
                s.push_back(contact(m));
                s.push_back(range(m, {-1, 0, -0.2}));
            }
            for (SensorSpec& x : s)
                x.enabled = enabled;
        }
        Simulation sim(w);
        test::drive_pitch_yaw_gait(sim);
        std::vector<double> out;
        for (int k = 0; k < 10; ++k) {
            sim.run(0.2);
            for (int b = 0; b < 7; ++b) {
                const Vec3 p = sim.body(0, b).pose.position;
                out.insert(out.end(), {p.x, p.y, p.z});
            }
        }
        return out;
    };
    const std::vector<double> none = trajectory(false, false);
    CHECK(trajectory(true, true) == none);
    CHECK(trajectory(true, false) == none);
}

TEST_CASE("controllers read their robot's sensors through ControlIO at the start of the tick") {
    // records what it sees of the sensors of its robot at each step
    class Probe final : public Controller {
      public:
        Probe() : Controller(ControllerDef{"probe", {}, {}}) {}
        void step(ControlIO& io) override {
            count = io.sensor_count();
            k = io.find_sensor("joint1");
            missing = io.find_sensor("imu9");
            if (k >= 0 && io.sensor(k).enabled) seen.push_back(io.sensor_values(k)[0]);
            io.set_target(0, 0.5);
        }
        int count = 0, k = -2, missing = 0;
        std::vector<double> seen;
    };
    WorldSpec w = test::chain_world(3, Connection::pitch_pitch);
    w.robots[0].robot.sensors = {contact(0), joint_sensor(0)};
    Simulation sim(w);
    auto probe = std::make_shared<Probe>();
    Drive d;
    d.joints = {0};
    d.controller = probe;
    sim.add_drive(0, d);
    // the angle the controller sees at each think is the joint's angle when the tick began
    std::vector<double> at_think;
    sim.add_observer([&](const Simulation& s) {
        if (s.ticks() % s.options().control_every == 0) at_think.push_back(s.joint(0, 0).angle);
    });
    at_think.push_back(sim.joint(0, 0).angle);
    sim.run(0.3);
    CHECK(probe->count == 2);
    CHECK(probe->k == 1);
    CHECK(probe->missing == -1);
    REQUIRE(probe->seen.size() == 10);
    for (size_t t = 0; t < probe->seen.size(); ++t)
        CHECK(probe->seen[t] == at_think[t]);
    CHECK(probe->seen.back() > 0.1);  // it followed the target

    // switched off, the controller sees the switch and stops using it
    sim.set_sensor_enabled(sim.find_sensor(0, "joint1"), false);
    sim.run(0.3);
    CHECK(probe->seen.size() == 10);
}
