// Tests for engine/src/xml/urdf.cpp: exported robots pass ROS's check_urdf (liburdfdom-tools)
// and import back to the same bodies and joints; imported chains simulate like the original;
// what cannot be imported is rejected with file and line.
#include "gaitlab/urdf.h"

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "gaitlab/controllers/sine.h"
#include "gaitlab/simulation.h"
#include "gaitlab/xml.h"
#include "temp_dir.h"

using namespace gaitlab;
using Catch::Matchers::Equals;
using gaitlab::test::TempDir;

namespace {

// check_urdf's exit status and what it printed
std::pair<int, std::string> check_urdf(const std::string& path) {
    const std::string out = path + ".check";
    const int status = std::system(("check_urdf " + path + " > " + out + " 2>&1").c_str());
    return {status, test::read_text(out)};
}

void check_close(const Vec3& a, const Vec3& b) {
    CHECK(a.x == Approx(b.x).margin(1e-12));
    CHECK(a.y == Approx(b.y).margin(1e-12));
    CHECK(a.z == Approx(b.z).margin(1e-12));
}

void check_same_robot(const RobotSpec& a, const RobotSpec& b) {
    CHECK(a.name == b.name);
    REQUIRE(a.bodies.size() == b.bodies.size());
    REQUIRE(a.joints.size() == b.joints.size());
    for (size_t i = 0; i < a.bodies.size(); ++i) {
        CAPTURE(i);
        CHECK(a.bodies[i].name == b.bodies[i].name);
        CHECK(a.bodies[i].shape == b.bodies[i].shape);
        check_close(a.bodies[i].size, b.bodies[i].size);
        CHECK(a.bodies[i].mass == b.bodies[i].mass);
        check_close(a.bodies[i].pose.position, b.bodies[i].pose.position);
        const Quat& p = a.bodies[i].pose.orientation;
        const Quat& q = b.bodies[i].pose.orientation;
        CHECK(std::abs(p.w * q.w + p.x * q.x + p.y * q.y + p.z * q.z) == Approx(1).margin(1e-12));
    }
    for (size_t j = 0; j < a.joints.size(); ++j) {
        CAPTURE(j);
        CHECK(a.joints[j].name == b.joints[j].name);
        CHECK(a.joints[j].role == b.joints[j].role);
        CHECK(a.joints[j].parent == b.joints[j].parent);
        CHECK(a.joints[j].child == b.joints[j].child);
        check_close(a.joints[j].pivot, b.joints[j].pivot);
        check_close(a.joints[j].axis, b.joints[j].axis);
        CHECK(a.joints[j].min_angle == b.joints[j].min_angle);
        CHECK(a.joints[j].max_angle == b.joints[j].max_angle);
        CHECK(a.joints[j].servo.max_speed == b.joints[j].servo.max_speed);
        CHECK(a.joints[j].servo.max_torque == b.joints[j].servo.max_torque);
    }
}

std::string import_error(const std::string& text) {
    try {
        parse_urdf(text, "r.urdf");
    } catch (const FormatError& e) {
        return e.what();
    }
    FAIL("no error");
    return "";
}

const char* kLink = R"(<inertial><mass value="0.1"/></inertial>
    <collision><geometry><box size="0.1 0.05 0.05"/></geometry></collision>)";

}  // namespace

TEST_CASE("exported robots pass check_urdf and import back to the same robot") {
    TempDir dir("urdf");
    ModuleDef strong = default_module_def();
    strong.name = "strong";
    strong.max_angle = deg_to_rad(60);
    strong.servo.max_torque = 1.2;
    ModuleDef roller = default_module_def();
    roller.name = "roller";
    roller.shape = Shape::cylinder;
    roller.radius = 0.03;
    roller.axis = JointAxis::twist;
    const RobotSpec robots[] = {
        make_chain(ChainSpec{"pp8", 8, Connection::pitch_pitch, default_module_def()}),
        make_chain(ChainSpec{"py5", 5, Connection::pitch_yaw, default_module_def()}),
        make_chain(ChainSpec{"strong", 1, Connection::yaw_yaw, strong}),
        make_chain(ChainSpec{"rollers", 3, Connection::pitch_pitch, roller}),
    };
    for (const RobotSpec& robot : robots) {
        CAPTURE(robot.name);
        const std::string path = dir.file(robot.name + ".urdf");
        write_urdf(path, robot);
        const auto [status, out] = check_urdf(path);
        INFO(out);
        CHECK(status == 0);
        CHECK_THAT(out, Catch::Contains("Successfully Parsed XML"));
        CHECK_THAT(out, Catch::Contains("root Link: tail"));
        check_same_robot(read_urdf(path), robot);
    }
}

TEST_CASE("a robot with turned bodies exports and imports its orientations") {
    RobotSpec robot =
        make_chain(ChainSpec{"bent", 2, Connection::pitch_pitch, default_module_def()});
    robot.chain.reset();
    // turned about z only: import rests the lowest point on the floor, which a tilt would move
    robot.bodies[1].pose.orientation = Quat::from_axis_angle({0, 0, 1}, 0.4);
    TempDir dir("urdf_turned");
    write_urdf(dir.file("bent.urdf"), robot);
    CHECK(check_urdf(dir.file("bent.urdf")).first == 0);
    check_same_robot(read_urdf(dir.file("bent.urdf")), robot);
}

TEST_CASE("an imported chain moves like the robot it was exported from") {
    const RobotSpec original =
        make_chain(ChainSpec{"snake", 6, Connection::pitch_pitch, default_module_def()});
    const RobotSpec imported = parse_urdf(format_urdf(original), "snake.urdf");
    Vec3 moved[2];
    int k = 0;
    for (const RobotSpec* robot : {&original, &imported}) {
        WorldSpec world;
        world.floor.friction = 0.8;
        auto sine = std::make_shared<controllers::Sine>();
        world.robots.push_back({*robot, {}, {{select_joints(*robot, "pitch"), sine}}});
        Simulation sim(world);
        sim.run(5);
        moved[k++] = sim.robot_displacement(0);
    }
    CAPTURE(moved[0].x, moved[1].x);
    CHECK(moved[0].norm() > 0.05);
    CHECK(moved[1].x == Approx(moved[0].x).epsilon(0.02));
}

TEST_CASE("URDF that is not a serial chain of revolute joints with boxes is rejected") {
    const std::string link = kLink;
    CHECK_THAT(import_error("<robot name=\"r\">\n<link name=\"a\">" + link +
                            "</link>\n<link name=\"b\">" + link +
                            "</link>\n<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/>"
                            "<child link=\"b\"/></joint>\n</robot>"),
               Equals("r.urdf:6: robot/joint[1]: only revolute joints can be imported (got type "
                      "'continuous')"));
    CHECK_THAT(import_error("<robot name=\"r\">\n<link name=\"a\"><inertial><mass value=\"1\"/>"
                            "</inertial>\n<collision><geometry><mesh filename=\"a.stl\"/>"
                            "</geometry></collision></link>\n</robot>"),
               Equals("r.urdf:3: robot/link[1]/collision[1]/geometry[1]/mesh[1]: only box and "
                      "cylinder geometry can be imported (got <mesh>)"));
    CHECK_THAT(
        import_error("<robot name=\"r\">\n<link name=\"a\">" + link + "</link>\n<link name=\"b\">" +
                     link + "</link>\n<link name=\"c\">" + link +
                     "</link>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>"
                     "<child link=\"b\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
                     "velocity=\"1\"/></joint>\n<joint name=\"k\" type=\"revolute\"><parent "
                     "link=\"a\"/><child link=\"c\"/><limit lower=\"-1\" upper=\"1\" "
                     "effort=\"1\" velocity=\"1\"/></joint>\n</robot>"),
        Equals("r.urdf:9: robot/joint[2]: link 'a' has two child links: only serial "
               "chains can be imported"));
    CHECK_THAT(import_error("<robot name=\"r\">\n<link name=\"a\">" + link +
                            "</link>\n<link name=\"b\">" + link +
                            "</link>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>"
                            "<child link=\"b\"/></joint>\n</robot>"),
               Equals("r.urdf:6: robot/joint[1]: a revolute joint needs a <limit lower upper "
                      "effort velocity>"));
    CHECK_THAT(import_error("<gaitlab version=\"1\"/>"),
               Equals("r.urdf:1: expected a <robot> root element, got <gaitlab>"));
}

TEST_CASE("a link whose body is invalid is named at its own line", "[lines]") {
    const std::string link = kLink;
    CHECK_THAT(import_error("<robot name=\"r\">\n<link name=\"a\">" + link +
                            "</link>\n<link name=\"b\"><inertial><mass value=\"1\"/></inertial>"
                            "<collision><geometry><box size=\"0.1 -0.1 0.1\"/></geometry>"
                            "</collision></link>\n</robot>"),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' size y must be positive (got "
                      "-0.1 m)"));
    CHECK_THAT(
        import_error(""),
        Equals("r.urdf:1: malformed XML: the file holds no element (it is empty, or spaces only)"));
}
