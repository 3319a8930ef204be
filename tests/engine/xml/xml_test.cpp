// Tests for engine/src/xml/: every file format round-trips exactly (spec -> XML -> spec), and
// every reader rejects bad input with "FILE:LINE: PATH: message", suggesting the closest valid
// name for unknown elements and attributes; writers check before writing and write atomically.
#include "gaitlab/xml.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "gaitlab/files.h"
#include "temp_dir.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using gaitlab::test::TempDir;

namespace {

std::string doc(const std::string& inner) {
    return "<?xml version=\"1.0\"?>\n<gaitlab version=\"1\">\n" + inner + "\n</gaitlab>\n";
}

std::string robot_error(const std::string& inner) {
    try {
        parse_robot(doc(inner), "robot.xml");
    } catch (const FormatError& e) {
        return e.what();
    }
    FAIL("no error for: " << inner);
    return "";
}

std::string actuation_error(const std::string& inner) {
    try {
        parse_actuation(doc(inner), "act.xml");
    } catch (const FormatError& e) {
        return e.what();
    }
    FAIL("no error for: " << inner);
    return "";
}

std::string environment_error(const std::string& inner) {
    try {
        parse_environment(doc(inner), "env.xml");
    } catch (const FormatError& e) {
        return e.what();
    }
    FAIL("no error for: " << inner);
    return "";
}

}  // namespace

TEST_CASE("a chain robot round-trips as a chain") {
    for (Connection c : {Connection::pitch_pitch, Connection::pitch_yaw, Connection::yaw_yaw}) {
        ChainSpec chain;
        chain.name = "snake";
        chain.modules = 7;
        chain.connection = c;
        const RobotSpec robot = make_chain(chain);
        const std::string text = format_robot(robot);
        CHECK(text.find("<chain modules=\"7\"") != std::string::npos);
        CHECK(text.find("module=\"y1\"") != std::string::npos);
        CHECK(parse_robot(text, "r.xml") == robot);
    }
}

TEST_CASE("a chain of a custom module round-trips, angles typed in degrees exactly") {
    ChainSpec chain;
    chain.name = "big";
    chain.modules = 3;
    chain.module.name = "wide";
    chain.module.width = 0.08;
    chain.module.mass = 0.123;
    chain.module.min_angle = deg_to_rad(-37.3);
    chain.module.max_angle = deg_to_rad(61.7);
    chain.module.servo.max_torque = 1.5;
    const RobotSpec robot = make_chain(chain);
    const std::string text = format_robot(robot);
    CHECK(text.find("min=\"-37.3\" max=\"61.7\"") != std::string::npos);
    CHECK(parse_robot(text, "r.xml") == robot);
}

TEST_CASE("chains of library modules are saved by name, cylinder and twist modules in full") {
    const RobotSpec cube = make_chain(ChainSpec{"c", 3, Connection::pitch_yaw, cube_module_def()});
    const std::string text = format_robot(cube);
    CHECK(text.find("module=\"cube\"") != std::string::npos);
    CHECK(parse_robot(text, "r.xml") == cube);
    ModuleDef roller = default_module_def();
    roller.name = "roller";
    roller.shape = Shape::cylinder;
    roller.radius = 0.03;
    roller.axis = JointAxis::twist;
    roller.servo.max_speed = 3;
    const RobotSpec rolling = make_chain(ChainSpec{"r", 4, Connection::pitch_pitch, roller});
    const std::string rolled = format_robot(rolling);
    CHECK(rolled.find("shape=\"cylinder\"") != std::string::npos);
    CHECK(rolled.find("axis=\"twist\"") != std::string::npos);
    const RobotSpec back = parse_robot(rolled, "r.xml");
    CHECK(back == rolling);
    CHECK(back.joints[0].role == JointRole::roll);
    CHECK(back.bodies[1].shape == Shape::cylinder);
    // the same robot written body by body keeps its shapes and roles
    RobotSpec parts = rolling;
    parts.chain.reset();
    CHECK(parse_robot(format_robot(parts), "r.xml") == parts);
}

TEST_CASE("a robot that is not a chain round-trips body by body") {
    RobotSpec robot = make_chain(ChainSpec{"arm", 2, Connection::pitch_yaw, default_module_def()});
    robot.chain.reset();
    robot.bodies[1].pose.orientation = Quat::from_axis_angle({0, 0, 1}, 0.3);
    robot.bodies[2].friction = 0.25;
    robot.joints[1].servo.kp = 12;
    robot.joints[0].max_angle = deg_to_rad(45);
    robot.self_collision = true;
    // a given inertia, here on one body: the others keep their solid's and write none
    robot.bodies[1].inertia = Vec3{1e-5, 2.5e-5, 3e-5};
    // and a centre of mass off its shape's centre, on another: written only where given
    robot.bodies[2].center_of_mass = Vec3{-0.01, 0.005, 0};
    const std::string text = format_robot(robot);
    CHECK(text.find("com=\"-0.01 0.005 0\"") != std::string::npos);
    CHECK(text.find("com=") == text.rfind("com="));
    CHECK(text.find("inertia=\"1e-05 2.5e-05 3e-05\"") != std::string::npos);
    CHECK(text.find("inertia=") == text.rfind("inertia="));
    CHECK(text.find("<chain") == std::string::npos);
    CHECK(text.find("<body name=\"segment1\"") != std::string::npos);
    CHECK(text.find("parent=\"tail\" child=\"segment1\"") != std::string::npos);
    CHECK(parse_robot(text, "r.xml") == robot);
}

TEST_CASE("sensors round-trip with the robot, each with the fields of its kind") {
    RobotSpec robot =
        make_chain(ChainSpec{"snake", 4, Connection::pitch_yaw, default_module_def()});
    SensorSpec joint{SensorKind::joint, "j2", 0, 1};
    SensorSpec imu{SensorKind::imu, "imu_tail", 2, 0, ModuleHalf::tail};
    SensorSpec contact{SensorKind::contact, "contact4", 3};
    SensorSpec range{SensorKind::range, "eye", 3, 0, ModuleHalf::head, {1, 0, -0.5}, 1.5, false};
    SensorSpec position{SensorKind::position, "position"};
    robot.sensors = {joint, imu, contact, range, position};
    const std::string text = format_robot(robot);
    CHECK(text.find("<sensor kind=\"range\" name=\"eye\" module=\"4\" half=\"head\" "
                    "direction=\"1 0 -0.5\" max_range=\"1.5\" enabled=\"false\"/>") !=
          std::string::npos);
    CHECK(parse_robot(text, "r.xml") == robot);
    // a sensor without a name takes its default one
    const RobotSpec named = parse_robot(
        doc("<robot><chain modules=\"3\"/><sensor kind=\"imu\" module=\"2\"/></robot>"), "r.xml");
    REQUIRE(named.sensors.size() == 1);
    CHECK(named.sensors[0].name == "imu2");
}

TEST_CASE("robot files reject bad input with file, line, element path and a suggestion") {
    CHECK_THAT(robot_error("<robot><chain modules=\"3\"/>\n<sensor kind=\"imu\" module=\"4\"/>"
                           "</robot>"),
               Equals("robot.xml:4: robot/sensor[1]: robot 'robot' has no module 4 (it has "
                      "modules 1 to 3)"));
    CHECK_THAT(robot_error("<robot><chain modules=\"3\"/>\n<sensor kind=\"lidar\"/></robot>"),
               Equals("robot.xml:4: robot/sensor[1]: unknown sensor kind 'lidar' (expected "
                      "'joint', 'imu', 'contact', 'range' or 'position')"));
    CHECK_THAT(robot_error("<robot><chain modules=\"3\"/>\n<sensor kind=\"contact\" "
                           "max_range=\"2\"/></robot>"),
               Equals("robot.xml:4: robot/sensor[1]: unknown attribute 'max_range' (expected "
                      "'kind', 'name', 'module', 'enabled')"));
    CHECK_THAT(robot_error("<robot>\n<chain modules=\"8\" conection=\"pitch-pitch\"/>\n</robot>"),
               Equals("robot.xml:4: robot/chain[1]: unknown attribute 'conection'; did you mean "
                      "'connection'? (expected 'modules', 'connection', 'module')"));
    CHECK_THAT(robot_error("<robot>\n<chian modules=\"8\"/>\n</robot>"),
               Equals("robot.xml:4: robot/chian: unknown element <chian>; did you mean "
                      "'chain'? (expected 'chain', 'body', 'joint', 'sensor')"));
    CHECK_THAT(robot_error("<robot><chain modules=\"0\"/></robot>"),
               Equals("robot.xml:3: robot/chain[1]: modules must be in [1, 1000] (got 0)"));
    CHECK_THAT(robot_error("<robot><chain modules=\"eight\"/></robot>"),
               Equals("robot.xml:3: robot/chain[1]: attribute 'modules': integer expected, got "
                      "'eight'"));
    CHECK_THAT(robot_error("<robot><chain modules=\"2\" connection=\"pitch-roll\"/></robot>"),
               Equals("robot.xml:3: robot/chain[1]: unknown connection type 'pitch-roll' (expected "
                      "'pitch-pitch', 'pitch-yaw' or 'yaw-yaw')"));
    CHECK_THAT(robot_error("<robot><chain modules=\"2\">\n<module mass=\"-1\"/></chain></robot>"),
               Equals("robot.xml:4: robot/chain[1]/module[1]: module 'y1' mass must be positive "
                      "(got -1 kg)"));
    CHECK_THAT(
        robot_error(
            "<robot><chain modules=\"2\">\n<module min=\"40\" max=\"20\"/></chain></robot>"),
        Equals("robot.xml:4: robot/chain[1]/module[1]: module 'y1' joint range must satisfy -180 "
               "<= min < max <= 180 deg"));
    // a joint's range has its own bounds, however far outside (not a pose's ten turns)
    CHECK_THAT(
        robot_error(
            "<robot><chain modules=\"2\">\n<module min=\"-5000\" max=\"20\"/></chain></robot>"),
        Equals("robot.xml:4: robot/chain[1]/module[1]: module 'y1' joint range must satisfy -180 "
               "<= min < max <= 180 deg"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 1 1\" mass=\"1\"/>\n"
                           "<body name=\"b\" size=\"1 1 1\" mass=\"1\"/>\n"
                           "<joint name=\"j\" parent=\"a\" child=\"bb\" pivot=\"0 0 0\" "
                           "axis=\"0 1 0\"/>\n</robot>"),
               Equals("robot.xml:6: robot/joint[1]: attribute 'child': no body 'bb' above this "
                      "joint; did you mean 'b'?"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 0.5 0.5\" mass=\"1\" "
                           "com=\"0 0 0.3\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' com must lie inside the "
                      "box: each coordinate within half its size, ±0.5 ±0.25 ±0.25 m (got 0 0 "
                      "0.3 m)"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" shape=\"cylinder\" size=\"1 0.5 0.5\" "
                           "mass=\"1\" com=\"0 0.2 0.2\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' com must lie inside the "
                      "cylinder: x within ±0.5 m (half its length), y and z within 0.25 m of its "
                      "axis (its radius) (got 0 0.2 0.2 m)"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 1 1\" mass=\"1\" "
                           "com=\"nan 0 0\"/>\n</robot>"),
               Catch::StartsWith("robot.xml:4: robot/body[1]: attribute 'com': three numbers"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 1\" mass=\"1\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: attribute 'size': three numbers \"x y z\" "
                      "expected, got '1 1'"));
    CHECK_THAT(
        robot_error("<robot>\n<body name=\"a\" size=\"1 1 -1\" mass=\"1\"/>\n</robot>"),
        Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' size z must be positive (got "
               "-1 m)"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 1 1\" mass=\"1\" "
                           "inertia=\"0.1 0.1 0.3\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' inertia must have each "
                      "moment at most the sum of the other two, as every body's has (got 0.1 "
                      "0.1 0.3 kg·m²: z is 0.3, the other two add up to 0.2)"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" size=\"1 1 1\" mass=\"1\" "
                           "inertia=\"0.1 0.1\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: attribute 'inertia': three numbers \"x y z\" "
                      "expected, got '0.1 0.1'"));
    CHECK_THAT(robot_error("<robot/>"),
               Equals("robot.xml:3: robot: a robot needs a <chain>, or <body> and <joint> "
                      "elements"));
    CHECK_THAT(
        robot_error("<robot>\n<body name=\"a\" size=\"1 0.001 0.001\" mass=\"1\"/>\n</robot>"),
        Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' longest side must be at most "
               "300 times its second longest (got 1 x 0.001 x 0.001 m: 1000 times)"));
    CHECK_THAT(robot_error("<robot>\n<body name=\"a\" shape=\"cylinder\" size=\"1 0.002 0.002\" "
                           "mass=\"1\"/>\n</robot>"),
               Equals("robot.xml:4: robot/body[1]: robot 'robot' body 'a' length must be at most "
                      "300 times its diameter (got 1 m and 0.002 m: 500 times)"));
    CHECK_THAT(robot_error("<robot><chain modules=\"2\">\n<module length=\"1\" width=\"0.003\" "
                           "height=\"0.003\"/></chain></robot>"),
               Equals("robot.xml:4: robot/chain[1]/module[1]: module 'y1' bodies' longest side "
                      "must be at most 300 times its second longest (got 1 x 0.003 x 0.003 m: "
                      "333.333 times)"));
}

TEST_CASE("every reader checks the document: XML, root, version, kind") {
    CHECK_THAT(
        robot_error("<robot><chain modules=\"2\"></robot>"),
        Equals("robot.xml:3: malformed XML: the element that starts here is closed by an end "
               "tag of another name (an element <a ...> ends with </a>)"));
    try {
        parse_robot("<robot/>", "r.xml");
        FAIL("no error");
    } catch (const FormatError& e) {
        CHECK_THAT(e.what(), Equals("r.xml:1: expected a <gaitlab version=\"1\"> root element, got "
                                    "<robot>"));
        CHECK(e.file() == "r.xml");
        CHECK(e.line() == 1);
    }
    try {
        parse_robot("<gaitlab version=\"2\"><robot/></gaitlab>", "r.xml");
        FAIL("no error");
    } catch (const FormatError& e) {
        CHECK_THAT(e.what(), Equals("r.xml:1: gaitlab: version 2 is not supported (this gaitlab "
                                    "reads version 1)"));
    }
    try {
        parse_robot(doc("<environment/>"), "r.xml");
        FAIL("no error");
    } catch (const FormatError& e) {
        CHECK_THAT(e.what(), Equals("r.xml:3: gaitlab: expected <robot>, got <environment> (is "
                                    "this a robot file?)"));
    }
    CHECK_THROWS_WITH(
        read_robot("/no/such/robot.xml"),
        Equals("/no/such/robot.xml: cannot read the file: No such file or directory"));
}

TEST_CASE("actuation files round-trip groups by role or joints, with parameters") {
    ActuationSpec a;
    GroupSpec pitch;
    pitch.role = "pitch";
    pitch.controller.kind = ControllerRef::Kind::builtin;
    pitch.controller.name = "sine";
    pitch.controller.params = {{"amplitude", 30}, {"phase", -120.5}};
    GroupSpec some;
    some.joints = {1, 3, 5};
    some.controller.kind = ControllerRef::Kind::file;
    some.controller.name = "controllers/my_sine.lua";
    GroupSpec tmpl;
    tmpl.role = "yaw";
    tmpl.controller.kind = ControllerRef::Kind::template_;
    tmpl.controller.name = "cpg_chain";
    tmpl.controller.params = {{"coupling", 12.25}};
    a.groups = {pitch, some, tmpl};
    const std::string text = format_actuation(a);
    CHECK(text.find("<group joints=\"2 4 6\">") != std::string::npos);
    CHECK(text.find("<controller builtin=\"sine\" amplitude=\"30\" phase=\"-120.5\"/>") !=
          std::string::npos);
    const ActuationSpec back = parse_actuation(text, "a.xml");
    CHECK(back == a);
    CHECK(back.groups[1].controller.source == "a.xml");
    CHECK(back.groups[1].controller.line == 8);
}

TEST_CASE("actuation files reject bad groups and controllers") {
    CHECK_THAT(
        actuation_error("<actuation>\n<group joints=\"1 2 2\"><controller builtin=\"sine\"/>"
                        "</group></actuation>"),
        Equals("act.xml:4: actuation/group[1]: attribute 'joints': joint 2 is listed twice"));
    CHECK_THAT(
        actuation_error("<actuation>\n<group joints=\"pitch 3\"><controller builtin=\"sine\"/>"
                        "</group></actuation>"),
        Equals("act.xml:4: actuation/group[1]: attribute 'joints': 'pitch', 'yaw', 'all' "
               "or joint numbers (from 1) expected, got 'pitch 3'"));
    CHECK_THAT(actuation_error("<actuation>\n<group joints=\"all\"/></actuation>"),
               Equals("act.xml:4: actuation/group[1]: one <controller> per group expected"));
    CHECK_THAT(actuation_error("<actuation>\n<group joints=\"all\">\n<controller builtin=\"sine\" "
                               "file=\"x.lua\"/></group></actuation>"),
               Equals("act.xml:5: actuation/group[1]/controller[1]: exactly one of 'builtin', "
                      "'file' or 'template' expected (which controller), then its parameters, "
                      "e.g. <controller builtin=\"sine\" amplitude=\"30\"/>"));
    CHECK_THAT(actuation_error("<actuation>\n<group joints=\"all\">\n<controller builtin=\"sine\" "
                               "amplitude=\"big\"/></group></actuation>"),
               Equals("act.xml:5: actuation/group[1]/controller[1]: attribute 'amplitude': number "
                      "expected, got 'big'"));
    CHECK_THAT(actuation_error("<actuation>\n<groups/></actuation>"),
               Equals("act.xml:4: actuation/groups: unknown element <groups>; did you mean "
                      "'group'? (expected 'group')"));
}

TEST_CASE("a group resolves against its robot") {
    const RobotSpec robot =
        make_chain(ChainSpec{"s", 4, Connection::pitch_yaw, default_module_def()});
    GroupSpec g;
    g.role = "yaw";
    CHECK(resolve_group(g, robot) == std::vector<int>{1, 3});
    g.role.clear();
    g.joints = {0, 4};
    CHECK_THROWS_WITH(resolve_group(g, robot), "robot 's' has no joint 5 (it has joints 1 to 4)");
    g.joints.clear();
    CHECK_THROWS_WITH(resolve_group(g, robot), "a joint group needs at least one joint");
}

TEST_CASE("environment files round-trip gravity, floor, boxes and placements") {
    EnvironmentSpec env;
    env.world.gravity = {0, 0, -1.62};
    env.world.floor.friction = 0.35;
    BoxSpec still;
    still.size = {0.2, 0.1, 0.05};
    still.pose.position = {1, 0.5, 0.025};
    still.pose.orientation = Quat::from_axis_angle({0, 0, 1}, deg_to_rad(30));
    BoxSpec tilted;
    tilted.size = {0.1, 0.1, 0.1};
    tilted.pose.position = {-1, 0, 0.3};
    tilted.pose.orientation = Quat::from_axis_angle({1, 0, 0}, 0.2);
    tilted.mass = 0.5;
    tilted.friction = 0.6;
    env.world.boxes = {still, tilted};
    env.placements = {
        {"snake", {{0.1, -0.2, 0}, Quat::from_axis_angle({0, 0, 1}, deg_to_rad(-45))}}};
    const std::string text = format_environment(env);
    CHECK(text.find("yaw=\"30\"") != std::string::npos);
    CHECK(text.find("yaw=\"-45\"") != std::string::npos);
    CHECK(text.find("orientation=") != std::string::npos);  // not a pure yaw
    const EnvironmentSpec back = parse_environment(text, "e.xml");
    CHECK(back.world.gravity == env.world.gravity);
    CHECK(back.world.floor.friction == env.world.floor.friction);
    REQUIRE(back.world.boxes.size() == 2);
    for (size_t i = 0; i < 2; ++i) {
        CHECK(back.world.boxes[i].size == env.world.boxes[i].size);
        CHECK(back.world.boxes[i].pose.position == env.world.boxes[i].pose.position);
        CHECK(back.world.boxes[i].pose.orientation == env.world.boxes[i].pose.orientation);
        CHECK(back.world.boxes[i].mass == env.world.boxes[i].mass);
        CHECK(back.world.boxes[i].friction == env.world.boxes[i].friction);
    }
    REQUIRE(back.placements.size() == 1);
    CHECK(back.placements[0].robot == "snake");
    CHECK(back.placements[0].pose.position == env.placements[0].pose.position);
    CHECK(back.placements[0].pose.orientation == env.placements[0].pose.orientation);
}

TEST_CASE("the floor round-trips its stiffness and damping, the defaults written out, or rigid") {
    EnvironmentSpec env;
    env.world.floor.friction = 0.8;
    // the defaults are written, so the file keeps its physics if a default changes
    const std::string by_default = format_environment(env);
    CHECK(by_default.find("<floor friction=\"0.8\" stiffness=\"3000\" damping=\"60\"/>") !=
          std::string::npos);
    const EnvironmentSpec default_back = parse_environment(by_default, "e.xml");
    CHECK_FALSE(default_back.world.floor.rigid);
    CHECK(default_back.world.floor.stiffness == kDefaultFloorStiffness);
    CHECK(default_back.world.floor.damping == kDefaultFloorDamping);
    env.world.floor.rigid = true;
    const std::string rigid = format_environment(env);
    CHECK(rigid.find("<floor friction=\"0.8\" rigid=\"true\"/>") != std::string::npos);
    const EnvironmentSpec rigid_back = parse_environment(rigid, "e.xml");
    CHECK(rigid_back.world.floor.rigid);
    CHECK_FALSE(rigid_back.world.floor.stiffness);
    CHECK_FALSE(rigid_back.world.floor.damping);
    CHECK(format_environment(rigid_back) == rigid);
    env.world.floor.rigid = false;
    env.world.floor.stiffness = 12345.678901234567;
    env.world.floor.damping = 0.1;
    const std::string text = format_environment(env);
    CHECK(text.find("<floor friction=\"0.8\" stiffness=\"12345.678901234567\" damping=\"0.1\"/>") !=
          std::string::npos);
    const EnvironmentSpec back = parse_environment(text, "e.xml");
    REQUIRE(back.world.floor.stiffness);
    REQUIRE(back.world.floor.damping);
    CHECK(*back.world.floor.stiffness == *env.world.floor.stiffness);
    CHECK(*back.world.floor.damping == *env.world.floor.damping);
    CHECK(format_environment(back) == text);
    const EnvironmentSpec zero =
        parse_environment(doc("<environment><floor stiffness=\"1e4\" damping=\"0\"/>"
                              "</environment>"),
                          "e.xml");
    CHECK(zero.world.floor.stiffness == 1e4);
    CHECK(zero.world.floor.damping == 0.0);
    // one alone: the other keeps its default
    const EnvironmentSpec lone =
        parse_environment(doc("<environment><floor stiffness=\"1e4\"/></environment>"), "e.xml");
    CHECK(lone.world.floor.stiffness == 1e4);
    CHECK_FALSE(lone.world.floor.damping);
    CHECK(format_environment(lone).find("stiffness=\"10000\" damping=\"60\"") != std::string::npos);
}

TEST_CASE("a floor's bad values name the file, the line and what is expected") {
    CHECK_THAT(
        environment_error("<environment>\n<floor rigid=\"true\" stiffness=\"1e4\"/></environment>"),
        Equals("env.xml:4: environment/floor[1]: a rigid floor takes no stiffness (a floor is "
               "rigid, or compliant with a stiffness and a damping)"));
    CHECK_THAT(
        environment_error("<environment>\n<floor rigid=\"true\" damping=\"20\"/></environment>"),
        Equals("env.xml:4: environment/floor[1]: a rigid floor takes no damping (a floor is "
               "rigid, or compliant with a stiffness and a damping)"));
    CHECK_THAT(environment_error("<environment>\n<floor rigid=\"hard\"/></environment>"),
               Catch::StartsWith("env.xml:4: environment/floor[1]: attribute 'rigid'"));
    CHECK_THAT(
        environment_error("<environment>\n<floor stiffness=\"0\" damping=\"20\"/></environment>"),
        Equals("env.xml:4: environment/floor[1]: floor stiffness must be positive (got 0 N/m)"));
    CHECK_THAT(
        environment_error("<environment>\n<floor stiffness=\"1e4\" damping=\"-1\"/></environment>"),
        Equals("env.xml:4: environment/floor[1]: floor damping must not be negative (got "
               "-1 N·s/m)"));
    CHECK_THAT(
        environment_error("<environment>\n<floor stiffness=\"inf\" damping=\"1\"/></environment>"),
        Catch::StartsWith("env.xml:4: environment/floor[1]: "));
    CHECK_THAT(
        environment_error("<environment>\n<floor stiffness=\"hard\" damping=\"1\"/></environment>"),
        Catch::StartsWith("env.xml:4: environment/floor[1]: attribute 'stiffness'"));
    CHECK_THAT(environment_error("<environment>\n<floor stifness=\"1e4\"/></environment>"),
               Catch::Contains("did you mean 'stiffness'?"));
}

TEST_CASE("environment files reject values out of range before anything runs") {
    CHECK_THAT(environment_error("<environment>\n<floor friction=\"1.5\"/></environment>"),
               Equals("env.xml:4: environment/floor[1]: floor friction must be in [0, 1] (got "
                      "1.5)"));
    CHECK_THAT(environment_error("<environment>\n<box size=\"0.1 0.1 0.1\"/>\n"
                                 "<box size=\"0.1 0.1 0.1\" mass=\"-2\"/></environment>"),
               Equals("env.xml:5: environment/box[2]: box 2 mass must not be negative (got -2 "
                      "kg)"));
    CHECK_THAT(environment_error("<environment>\n<box size=\"0.1 0.1 0.1\" yaw=\"10\" "
                                 "orientation=\"1 0 0 0\"/></environment>"),
               Equals("env.xml:4: environment/box[1]: give 'yaw' or 'orientation', not both"));
    CHECK_THAT(environment_error("<environment>\n<place robot=\"a\"/>\n<place robot=\"a\"/>"
                                 "</environment>"),
               Equals("env.xml:5: environment/place[2]: robot 'a' is placed twice"));
    CHECK_THAT(environment_error("<environment>\n<place robot=\"a&#9;b\"/></environment>"),
               Equals("env.xml:4: environment/place[1]: robot name must be valid UTF-8 without "
                      "control characters (got \"a\\x09b\")"));
    // an angle of more than ten turns is refused: from about 1e16 rad its sine keeps none of
    // the written digits
    CHECK_THAT(environment_error("<environment>\n<box size=\"0.1 0.1 0.1\" yaw=\"1e300\"/>"
                                 "</environment>"),
               Equals("env.xml:4: environment/box[1]: attribute 'yaw': an angle in [-3600, 3600] "
                      "degrees (ten turns) expected, got 1e+300"));
    CHECK_NOTHROW(parse_environment(
        doc("<environment>\n<box size=\"0.1 0.1 0.1\" yaw=\"-3600\"/></environment>"), "env.xml"));
    CHECK_THAT(environment_error("<environment>\n<box size=\"0.1 0.1 0.1\" frction=\"1\"/>"
                                 "</environment>"),
               Equals("env.xml:4: environment/box[1]: unknown attribute 'frction'; did you mean "
                      "'friction'? (expected 'size', 'position', 'yaw', 'orientation', 'mass', "
                      "'friction')"));
}

TEST_CASE("environment files range-check gravity and heightfield heights", "[limits]") {
    CHECK_THAT(environment_error("<environment gravity=\"0 0 -1e30\">\n<floor/></environment>"),
               Equals("env.xml:3: environment: gravity z must be in [-1000, 1000] m/s² (got "
                      "-1e+30)"));
    CHECK_THAT(environment_error("<environment>\n<floor/>\n<heightfield samples=\"2 2\">\n"
                                 "<heights>0 0 0 2000</heights></heightfield></environment>"),
               Equals("env.xml:5: environment/heightfield[1]: heightfield 1 height at grid "
                      "point (2, 2) must be in [-1000, 1000] m (got 2000)"));
    CHECK_THAT(environment_error("<environment>\n<heightfield image=\"t.png\" "
                                 "max_height=\"1e9\"/></environment>"),
               Equals("env.xml:4: environment/heightfield[1]: heightfield 1 max_height must be "
                      "at most 1000 m (got 1000000000 m)"));
    CHECK_THAT(environment_error("<environment>\n<box position=\"1e30 0 0\"/></environment>"),
               Equals("env.xml:4: environment/box[1]: box 1 position x must be in [-10000, "
                      "10000] m (got 1e+30)"));
    // an image that cannot be read is named at the file's line when the file is read (it was
    // accepted, and the simulation failed later naming neither file nor line)
    CHECK_THAT(environment_error("<environment>\n<heightfield image=\"/nonexistent/t.png\"/>"
                                 "</environment>"),
               Equals("env.xml:4: environment/heightfield[1]: heightfield 1 cannot read image "
                      "'/nonexistent/t.png': no such file or directory"));
    CHECK_THAT(environment_error("<environment>\n<heightfield image=\"/dev/zero\"/>"
                                 "</environment>"),
               Catch::Contains("env.xml:4: environment/heightfield[1]: heightfield 1 cannot read "
                               "image '/dev/zero': not a regular file"));
    // and a file gaitlab could not read back is never written
    CHECK_THROWS_WITH(checked_environment_text(std::string(kMaxInputBytes + 1, ' ')),
                      Catch::StartsWith("the environment would be a file of 65 MiB, more than "
                                        "the 64 MiB gaitlab reads: make its heightfields"));
    CHECK(checked_environment_text("<environment/>") == "<environment/>");
}

TEST_CASE("simulation files round-trip and name missing parts by their resolved path") {
    TempDir dir("xml_sim");
    test::write_text(dir.file("env.xml"), doc("<environment/>"));
    test::write_text(dir.file("snake.xml"), doc("<robot><chain modules=\"3\"/></robot>"));
    SimulationFile s;
    s.name = "walk";
    s.duration = 12.5;
    s.options.dt = 0.0005;
    s.options.control_every = 20;
    s.options.solver_iterations = 30;
    s.options.seed = 42;
    s.options.on_controller_error = ControllerErrorPolicy::pause;
    s.options.solver = ConstraintSolver::pgs;  // not the default: it must round-trip
    s.environment = "env.xml";
    s.robots = {{"snake.xml", ""}};
    s.record.enabled = false;
    s.record.every = 5;
    s.record.flush_seconds = 0.5;
    write_simulation(dir.file("sim.xml"), s);
    const SimulationFile back = read_simulation(dir.file("sim.xml"));
    CHECK(back.name == "walk");
    CHECK(back.duration == 12.5);
    CHECK(back.options.dt == 0.0005);
    CHECK(back.options.control_every == 20);
    CHECK(back.options.solver_iterations == 30);
    CHECK(back.options.seed == 42);
    CHECK(back.options.on_controller_error == ControllerErrorPolicy::pause);
    CHECK(back.options.solver == ConstraintSolver::pgs);
    // the solver is written even at its default; a file without it gets the default
    s.options.solver = ConstraintSolver::block_nncg;
    write_simulation(dir.file("sim2.xml"), s);
    CHECK_THAT(test::read_text(dir.file("sim2.xml")), Catch::Contains("solver=\"block_nncg\""));
    test::write_text(dir.file("plain.xml"),
                     doc("<simulation><environment file=\"env.xml\"/></simulation>"));
    CHECK(read_simulation(dir.file("plain.xml")).options.solver == ConstraintSolver::block_nncg);
    // newton_steps is written only when given: not given, the simulation chooses for its world,
    // and every file before it round-trips unchanged; given, 0 included, it is written
    CHECK(s.options.newton_steps == kAutomaticNewtonSteps);
    CHECK_THAT(test::read_text(dir.file("sim2.xml")), !Catch::Contains("newton_steps"));
    CHECK(read_simulation(dir.file("plain.xml")).options.newton_steps == kAutomaticNewtonSteps);
    s.options.newton_steps = 0;
    write_simulation(dir.file("sim0.xml"), s);
    CHECK_THAT(test::read_text(dir.file("sim0.xml")), Catch::Contains("newton_steps=\"0\""));
    CHECK(read_simulation(dir.file("sim0.xml")).options.newton_steps == 0);
    s.options.newton_steps = 4;
    write_simulation(dir.file("sim3.xml"), s);
    CHECK_THAT(test::read_text(dir.file("sim3.xml")), Catch::Contains("newton_steps=\"4\""));
    CHECK(read_simulation(dir.file("sim3.xml")).options.newton_steps == 4);
    s.options.newton_steps = 0;
    CHECK(back.environment == "env.xml");
    REQUIRE(back.robots.size() == 1);
    CHECK(back.robots[0].robot == "snake.xml");
    CHECK(back.robots[0].actuation.empty());
    CHECK(back.record.enabled == false);
    CHECK(back.record.every == 5);
    CHECK(back.record.flush_seconds == 0.5);

    test::write_text(dir.file("bad.xml"), doc("<simulation>\n<environment file=\"env.xml\"/>\n"
                                              "<robot file=\"robots/snake.xml\"/>\n</simulation>"));
    const std::string missing = (dir.path / "robots" / "snake.xml").string();
    CHECK_THROWS_WITH(read_simulation(dir.file("bad.xml")),
                      dir.file("bad.xml") +
                          ":5: simulation/robot[1]: attribute 'file': cannot read " + missing +
                          ": No such file or directory");
    test::write_text(dir.file("bad2.xml"), doc("<simulation dt=\"0.5\">\n<environment "
                                               "file=\"env.xml\"/></simulation>"));
    CHECK_THROWS_WITH(
        read_simulation(dir.file("bad2.xml")),
        dir.file("bad2.xml") + ":3: simulation: dt must be in [1e-06, 0.1] s (got 0.5)");
    test::write_text(dir.file("bad4.xml"), doc("<simulation solver=\"fast\">\n<environment "
                                               "file=\"env.xml\"/></simulation>"));
    CHECK_THROWS_WITH(read_simulation(dir.file("bad4.xml")),
                      dir.file("bad4.xml") +
                          ":3: simulation: attribute 'solver': 'pgs' or "
                          "'block_nncg' expected, got 'fast'");
    test::write_text(dir.file("bad3.xml"), doc("<simulation/>"));
    CHECK_THROWS_WITH(read_simulation(dir.file("bad3.xml")),
                      dir.file("bad3.xml") +
                          ":3: simulation: an <environment file=\"...\"/> element is required");
}

TEST_CASE("simulation files refuse numbers that would wrap and parts that are not files",
          "[limits]") {
    TempDir dir("xml_sim_limits");
    test::write_text(dir.file("env.xml"), doc("<environment/>"));
    const auto error_of = [&](const std::string& sim) {
        test::write_text(dir.file("s.xml"), doc(sim));
        try {
            read_simulation(dir.file("s.xml"));
        } catch (const FormatError& e) {
            return std::string(e.what());
        }
        FAIL("no error for " << sim);
        return std::string();
    };
    const std::string at = dir.file("s.xml") + ":3: simulation: ";
    // 1e16 s at 1 ms used to overflow std::lround and run no tick at all
    CHECK(error_of("<simulation duration=\"1e16\"><environment file=\"env.xml\"/>"
                   "</simulation>") ==
          at + "duration must be in [0, 9.0072e+12] s at dt = 0.001 s (got 1e+16 s)");
    CHECK(error_of("<simulation control_every=\"4294967326\"><environment file=\"env.xml\"/>"
                   "</simulation>") ==
          at + "control_every must be in [1, 1000000] (got 4294967326)");
    // a name becomes run folder and file names: checked as a robot's
    CHECK(error_of("<simulation name=\"a&#9;b\"><environment file=\"env.xml\"/>"
                   "</simulation>") ==
          at + "simulation name must be valid UTF-8 without control characters (got \"a\\x09b\")");
    CHECK(error_of("<simulation>\n<environment file=\"env.xml\"/>\n<record "
                   "every=\"4294967297\"/></simulation>") ==
          dir.file("s.xml") +
              ":5: simulation/record[1]: every must be in [0, 1000000] (got 4294967297)");
    std::filesystem::create_directory(dir.file("folder.xml"));
    CHECK(error_of("<simulation>\n<environment file=\"folder.xml\"/></simulation>") ==
          dir.file("s.xml") + ":4: simulation/environment[1]: attribute 'file': cannot read " +
              dir.file("folder.xml") + ": is a directory");
    CHECK(error_of("<simulation>\n<environment file=\"/dev/null\"/></simulation>") ==
          dir.file("s.xml") +
              ":4: simulation/environment[1]: attribute 'file': cannot read /dev/null: not a "
              "regular file (a FIFO, device or socket)");
}

TEST_CASE("environment, robot and actuation files refuse counts that would wrap", "[limits]") {
    CHECK_THAT(environment_error("<environment>\n<stairs steps=\"4294967297\"/></environment>"),
               Equals("env.xml:4: environment/stairs[1]: steps must be in [1, 1000] (got "
                      "4294967297)"));
    CHECK_THAT(environment_error("<environment>\n<rubble count=\"-4294967296\"/></environment>"),
               Equals("env.xml:4: environment/rubble[1]: count must be in [0, 100000] (got "
                      "-4294967296)"));
    CHECK_THAT(environment_error("<environment>\n<pipe sides=\"99999999999\"/></environment>"),
               Equals("env.xml:4: environment/pipe[1]: sides must be in [3, 256] (got "
                      "99999999999)"));
    // module 4294967297 used to become module 1
    CHECK_THAT(robot_error("<robot>\n<chain modules=\"3\"/>\n<sensor kind=\"imu\" "
                           "module=\"4294967297\"/></robot>"),
               Equals("robot.xml:5: robot/sensor[1]: module must be in [1, 10000] (got "
                      "4294967297)"));
    CHECK_THAT(robot_error("<robot>\n<chain modules=\"4294967299\"/></robot>"),
               Equals("robot.xml:4: robot/chain[1]: modules must be in [1, 1000] (got "
                      "4294967299)"));
    CHECK_THAT(actuation_error("<actuation>\n<group joints=\"1 99999\"><controller "
                               "builtin=\"sine\"/></group></actuation>"),
               Equals("act.xml:4: actuation/group[1]: attribute 'joints': joint numbers must be "
                      "in [1, 10000] (got 99999)"));
    CHECK_THAT(actuation_error("<actuation>\n<group joints=\"1 99999999999999999999\">"
                               "<controller builtin=\"sine\"/></group></actuation>"),
               Catch::Matchers::Contains("joint numbers (from 1) expected"));
}

TEST_CASE("errors name the line of what is wrong: an empty file is line 1", "[lines]") {
    for (const auto& read : {+[](std::string_view t) { parse_robot(t, "f.xml"); },
                             +[](std::string_view t) { parse_actuation(t, "f.xml"); },
                             +[](std::string_view t) { parse_environment(t, "f.xml"); },
                             +[](std::string_view t) { parse_simulation(t, "f.xml"); }}) {
        CHECK_THROWS_WITH(
            read(""),
            "f.xml:1: malformed XML: the file holds no element (it is empty, or spaces only)");
        CHECK_THROWS_WITH(
            read("\n\n  \n"),
            "f.xml:1: malformed XML: the file holds no element (it is empty, or spaces only)");
    }
    // a body's error names the body, not the robot
    CHECK_THAT(robot_error("<robot name=\"s\">\n<body name=\"a\" size=\"1 1 1\" mass=\"1\"/>\n"
                           "<body name=\"b\" size=\"1 1 1\" mass=\"0\"/>\n</robot>"),
               Equals("robot.xml:5: robot/body[2]: robot 's' body 'b' mass must be positive (got "
                      "0 kg)"));
    CHECK_THAT(robot_error("<robot name=\"s\">\n<body name=\"a\" size=\"1 1 1\" mass=\"1\"/>\n"
                           "<body name=\"b\" size=\"1 1 1\" mass=\"1\"/>\n<joint name=\"j\" "
                           "parent=\"a\" child=\"b\" pivot=\"0 0 0\" axis=\"0 0 2\"/>\n</robot>"),
               Equals("robot.xml:6: robot/joint[1]: robot 's' joint 'j' axis must be a unit "
                      "vector"));
    CHECK_THAT(robot_error("<robot name=\"s\x01\">\n<chain modules=\"2\"/>\n</robot>"),
               Equals("robot.xml:4: robot/chain[1]: robot name must be valid UTF-8 without "
                      "control characters (got \"s\\x01\")"));
}

TEST_CASE("malformed XML says what is wrong in words, at its line", "[lines]") {
    // the messages were tinyxml2's codes (XML_ERROR_PARSING_TEXT), which say nothing to whoever
    // wrote the file
    const auto error = [](const std::string& text) {
        try {
            parse_robot(text, "f.xml");
        } catch (const FormatError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(error("<?xml version=\"1.0\"?>\n<gaitlab version=\"1\">\n<robot name=\"s\">\n"
                "<chain modules=\"2\"/>\n</robot>\n") ==
          "f.xml:2: malformed XML: the element that starts here is never closed (its end tag is "
          "missing, or the file ends early)");
    CHECK(error("<gaitlab version=\"1\">\n<robot name=s>\n</robot>\n</gaitlab>\n") ==
          "f.xml:2: malformed XML: an attribute that is not name=\"value\" (values are quoted)");
    CHECK(error("notes about my robot\n") ==
          "f.xml:1: malformed XML: text where an element is expected (a stray '<' or '&', or text "
          "outside the root element; write &lt; and &amp; for the characters themselves)");
    CHECK(error("<gaitlab version=\"1\">\n<!-- a comment\n</gaitlab>\n") ==
          "f.xml:2: malformed XML: a comment that does not end with -->");
    CHECK(error("<gaitlab version=\"1\">\n<robot name=\"s\">\n</gaitlab>\n") ==
          "f.xml:2: malformed XML: the element that starts here is closed by an end tag of "
          "another name (an element <a ...> ends with </a>)");
}

TEST_CASE("writers check before writing and replace files atomically") {
    TempDir dir("xml_write");
    const std::string path = dir.file("robot.xml");
    const RobotSpec good =
        make_chain(ChainSpec{"good", 2, Connection::pitch_pitch, default_module_def()});
    write_robot(path, good);
    const std::string before = test::read_text(path);
    RobotSpec bad = good;
    bad.bodies[0].mass = -1;
    CHECK_THROWS_AS(write_robot(path, bad), SpecError);
    CHECK(test::read_text(path) == before);  // nothing written when validation fails
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path),
                        std::filesystem::directory_iterator()) == 1);  // no temporary file left
    CHECK(read_robot(path) == good);
    // missing folders are made; a file in the way of one is named
    write_robot(dir.file("no/such/dir/robot.xml"), good);
    CHECK(read_robot(dir.file("no/such/dir/robot.xml")) == good);
    CHECK_THROWS_WITH(write_robot(dir.file("robot.xml/sub/robot.xml"), good),
                      "cannot write " + dir.file("robot.xml/sub/robot.xml") +
                          ": cannot create folder " + dir.file("robot.xml") +
                          ": a file of that name is in the way");
}

TEST_CASE("a simulation file's newton_steps is checked at its line") {
    TempDir dir("xml_newton");
    test::write_text(dir.file("env.xml"), doc("<environment/>"));
    const std::string file = dir.file("sim.xml");
    const auto error = [&](const std::string& attr) {
        test::write_text(
            file, doc("<simulation " + attr + ">\n<environment file=\"env.xml\"/>\n</simulation>"));
        try {
            read_simulation(file);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(error("newton_steps=\"4\"") == "no error");
    CHECK(error("newton_steps=\"-1\"") ==
          file + ":3: simulation: newton_steps must be in [0, 100] (got -1)");
    CHECK(error("newton_steps=\"101\"") ==
          file + ":3: simulation: newton_steps must be in [0, 100] (got 101)");
    CHECK(error("newton_steps=\"2.5\"") ==
          file + ":3: simulation: attribute 'newton_steps': integer expected, got '2.5'");
    CHECK(error("newton_steps=\"four\"") ==
          file + ":3: simulation: attribute 'newton_steps': integer expected, got 'four'");
    CHECK(error("newton_steps=\"4\" solver=\"pgs\"") ==
          file +
              ":3: simulation: newton_steps = 4 needs solver = 'block_nncg' (got solver = "
              "'pgs'; newton_steps must be 0 with it)");
    CHECK(error("solver=\"pgs\" newton_steps=\"0\"") == "no error");
}
