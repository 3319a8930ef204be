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
        REQUIRE(a.bodies[i].inertia.has_value() == b.bodies[i].inertia.has_value());
        if (a.bodies[i].inertia) check_close(*a.bodies[i].inertia, *b.bodies[i].inertia);
        REQUIRE(a.bodies[i].center_of_mass.has_value() == b.bodies[i].center_of_mass.has_value());
        if (a.bodies[i].center_of_mass) {
            check_close(*a.bodies[i].center_of_mass, *b.bodies[i].center_of_mass);
        }
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

TEST_CASE("a link smaller or lighter than a body may be is refused at its line", "[lines]") {
    // link b's mass and geometry (b on line 4: link a's text has a line break), checked at the
    // link before its <inertia> (which has bounds of its own, below)
    const auto with_b = [](const std::string& mass, const std::string& geometry) {
        return "<robot name=\"r\">\n<link name=\"a\">" + std::string(kLink) +
               "</link>\n<link name=\"b\"><inertial><mass value=\"" + mass +
               "\"/><inertia ixx=\"1e-300\" ixy=\"0\" ixz=\"0\" iyy=\"1e-300\" iyz=\"0\" "
               "izz=\"1e-300\"/></inertial><collision><geometry>" +
               geometry +
               "</geometry></collision></link>\n<joint name=\"j\" type=\"revolute\"><parent "
               "link=\"a\"/><child link=\"b\"/><limit lower=\"-1\" upper=\"1\" "
               "effort=\"0.5\" velocity=\"5\"/></joint>\n</robot>";
    };
    CHECK_THAT(import_error(with_b("1e-40", "<box size=\"0.1 0.05 0.05\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' mass must be at least 1e-09 kg "
                      "(got 1e-40 kg)"));
    CHECK_THAT(import_error(with_b("0.1", "<box size=\"0.1 1e-300 0.05\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' size y must be at least 0.0001 "
                      "m (got 1e-300 m)"));
    CHECK_THAT(import_error(with_b("0.1", "<cylinder radius=\"0.0005\" length=\"0.1\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' size y (a cylinder's "
                      "diameter) must be at least 0.002 m (got 0.001 m)"));
    CHECK_THAT(import_error(with_b("0.1", "<cylinder radius=\"0.01\" length=\"1e-5\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' size x must be at least 0.0001 "
                      "m (got 1e-05 m)"));
    // a slender link: its longest side over its second longest, a cylinder's length over its
    // diameter
    CHECK_THAT(import_error(with_b("0.1", "<box size=\"0.001 1 0.001\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' longest side must be at most "
                      "300 times its second longest (got 0.001 x 1 x 0.001 m: 1000 times)"));
    CHECK_THAT(import_error(with_b("0.1", "<cylinder radius=\"0.001\" length=\"1\"/>")),
               Equals("r.urdf:4: robot/link[2]: robot 'r' body 'b' length must be at most 300 "
                      "times its diameter (got 1 m and 0.002 m: 500 times)"));
    // a mass and geometry at the bounds are a body; its inertia is not
    std::string at_bounds = with_b("1e-9", "<cylinder radius=\"0.001\" length=\"0.0001\"/>");
    CHECK_THAT(import_error(at_bounds),
               Catch::StartsWith("r.urdf:4: robot/link[2]/inertial[1]/inertia[1]: robot 'r' body "
                                 "'b' inertia x must be in [5e-18, 2.0025e-15] kg·m² for its "
                                 "mass and size (got 1e-300)"));
    const size_t inertia = at_bounds.find("<inertia ");
    at_bounds.erase(inertia, at_bounds.find("/>", inertia) + 2 - inertia);
    const RobotSpec robot = parse_urdf(at_bounds, "r.urdf");
    REQUIRE(robot.bodies.size() == 2);
    CHECK(robot.bodies[1].mass == 1e-9);
    check_close(robot.bodies[1].size, {1e-4, 2e-3, 2e-3});
}

namespace {

// a two-link chain a - j - b, one element a line: <robot> on line 1, link a on 2, link b on 3,
// the joint on 4 with its <origin> on 5, <axis> on 6 and <limit> on 7
std::string chain_urdf(const std::string& origin, const std::string& axis, const std::string& limit,
                       const std::string& b_origin = "0 0 0", const std::string& joint = "j") {
    const std::string link = R"(<inertial><mass value="0.1"/></inertial><collision><origin xyz=")";
    const std::string box = R"("/><geometry><box size="0.1 0.05 0.05"/></geometry></collision>)";
    return "<robot name=\"r\">\n<link name=\"a\">" + link + "0 0 0" + box + "</link>\n" +
           "<link name=\"b\">" + link + b_origin + box + "</link>\n" + "<joint name=\"" + joint +
           "\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n" + "<origin xyz=\"" +
           origin + "\"/>\n" + "<axis xyz=\"" + axis + "\"/>\n" + "<limit " + limit +
           "/>\n</joint>\n</robot>";
}

const char* kLimit = R"(lower="-1" upper="1" effort="0.5" velocity="5")";

}  // namespace

TEST_CASE("a link gives its inertial, collision and their parts once", "[lines]") {
    // each second one used to be taken silently in place of the first
    const auto link = [](const std::string& inside) {
        return "<robot name=\"r\">\n<link name=\"a\">\n" + inside + "\n</link>\n</robot>";
    };
    const std::string box = R"(<geometry><box size="0.1 0.05 0.05"/></geometry>)";
    const std::string mass = R"(<inertial><mass value="0.1"/></inertial>)";
    CHECK_THAT(import_error(link(mass + "<collision>" + box + "</collision>\n" + mass)),
               Equals("r.urdf:4: robot/link[1]/inertial[2]: one <inertial> per link expected"));
    CHECK_THAT(import_error(link(R"(<inertial><mass value="0.1"/>)"
                                 "\n"
                                 R"(<mass value="0.2"/></inertial><collision>)" +
                                 box + "</collision>")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/mass[2]: one <mass> per <inertial> "
                      "expected"));
    CHECK_THAT(import_error(link(R"(<inertial><mass value="0.1"/><origin xyz="0 0 0"/>)"
                                 "\n"
                                 R"(<origin xyz="0.1 0 0"/></inertial><collision>)" +
                                 box + "</collision>")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/origin[2]: one <origin> per "
                      "<inertial> expected"));
    CHECK_THAT(import_error(link(mass + "<collision>" + box + "</collision>\n<collision>" + box +
                                 "</collision>")),
               Equals("r.urdf:4: robot/link[1]/collision[2]: one <collision> per link expected: "
                      "a link becomes one body, one box or cylinder"));
    CHECK_THAT(import_error(link(mass + "<collision><geometry><box size=\"0.1 0.05 0.05\"/>\n"
                                        "<cylinder radius=\"0.1\" length=\"0.2\"/></geometry>"
                                        "</collision>")),
               Equals("r.urdf:4: robot/link[1]/collision[1]/geometry[1]/cylinder[1]: one shape "
                      "per <collision> expected"));
    // a <visual> beside the <collision>, and several visuals without one, are as before: the
    // collision's shape, else the first visual's
    CHECK_NOTHROW(parse_urdf(link(mass + "<visual>" + box + "</visual><collision>" + box +
                                  "</collision><visual>" + box + "</visual>"),
                             "r.urdf"));
    const RobotSpec visuals = parse_urdf(
        link(mass + "<visual>" + box + "</visual><visual><geometry><box size=\"1 1 1\"/>" +
             "</geometry></visual>"),
        "r.urdf");
    CHECK(visuals.bodies[0].size == Vec3{0.1, 0.05, 0.05});
}

TEST_CASE("a joint's range and servo are named at its limit element", "[lines]") {
    CHECK_NOTHROW(parse_urdf(chain_urdf("0.1 0 0", "0 1 0", kLimit), "r.urdf"));
    CHECK_THAT(import_error(chain_urdf("0.1 0 0", "0 1 0",
                                       R"(lower="1" upper="-1" effort="0.5" velocity="5")")),
               Equals("r.urdf:7: robot/joint[1]/limit[1]: robot 'r' joint 'j' range must have "
                      "min < max"));
    CHECK_THAT(import_error(chain_urdf("0.1 0 0", "0 1 0",
                                       R"(lower="-1" upper="1" effort="0.5" velocity="0")")),
               Equals("r.urdf:7: robot/joint[1]/limit[1]: robot 'r' joint 'j' servo max_speed "
                      "must be positive (got 0 rad/s)"));
    CHECK_THAT(import_error(chain_urdf("0.1 0 0", "0 1 0",
                                       R"(lower="-1" upper="1" effort="-2" velocity="5")")),
               Equals("r.urdf:7: robot/joint[1]/limit[1]: robot 'r' joint 'j' servo max_torque "
                      "must be positive (got -2 N·m)"));
}

TEST_CASE("a joint's name is checked at the joint and its axis at the axis element", "[lines]") {
    CHECK_THAT(import_error(chain_urdf("0.1 0 0", "0 1 0", kLimit, "0 0 0", "j\x01")),
               Equals("r.urdf:4: robot/joint[1]: robot 'r' joint 'j\x01' name must be valid "
                      "UTF-8 without control characters (got \"j\\x01\")"));
    // an axis too long or too short to square is still an axis
    for (const char* axis : {"0 1e300 0", "0 1e-320 0"}) {
        CAPTURE(axis);
        const RobotSpec r = parse_urdf(chain_urdf("0.1 0 0", axis, kLimit), "r.urdf");
        CHECK(r.joints[0].axis == Vec3{0, 1, 0});
    }
}

TEST_CASE("positions out of range are named at the origin that puts them there", "[lines]") {
    // the joint's origin takes its pivot out of range
    CHECK_THAT(import_error(chain_urdf("1e30 0 0", "0 1 0", kLimit)),
               Equals("r.urdf:5: robot/joint[1]/origin: robot 'r' joint 'j' pivot must be in "
                      "[-1000000, 1000000] m (got 1e+30)"));
    // the pivot is in range, the child link's own origin is not
    CHECK_THAT(import_error(chain_urdf("0.1 0 0", "0 1 0", kLimit, "0 0 2e6")),
               Equals("r.urdf:3: robot/link[2]/collision[1]/origin: robot 'r' body 'b' "
                      "position must be in [-1000000, 1000000] m (got 2000000)"));
    // each in range in the root link's frame, but not once the robot is put on the floor
    CHECK_THAT(import_error(chain_urdf("-1e6 0 0", "0 1 0", kLimit)),
               Equals("r.urdf:2: robot/link[1]: robot 'r' body 'a' position must be in "
                      "[-1000000, 1000000] m (got 1000000.05)"));
}

TEST_CASE("joints that do not make a chain of known links are named at their line", "[lines]") {
    const std::string link = kLink;
    const std::string limit = R"(<limit lower="-1" upper="1" effort="1" velocity="1"/>)";
    const auto joint = [&](const std::string& name, const std::string& parent,
                           const std::string& child) {
        return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
               "\"/><child link=\"" + child + "\"/>" + limit + "</joint>\n";
    };
    const std::string ab = "<robot name=\"r\">\n<link name=\"a\">" + link +
                           "</link>\n<link name=\"b\">" + link + "</link>\n";
    CHECK_THAT(import_error(ab + joint("j", "a", "ghost") + "</robot>"),
               Equals("r.urdf:6: robot/joint[1]: joint 'j' names no link 'ghost'"));
    CHECK_THAT(import_error(ab + joint("j", "b", "b") + "</robot>"),
               Equals("r.urdf:6: robot/joint[1]: a joint must join two different links (parent "
                      "and child are both 'b')"));
    CHECK_THAT(import_error(ab + joint("j", "a", "b") + "<link name=\"c\">" + link + "</link>\n" +
                            joint("j", "b", "c") + "</robot>"),
               Equals("r.urdf:9: robot/joint[2]: a second joint named 'j'"));
    CHECK_THAT(import_error(ab + joint("j", "a", "b") + joint("k", "b", "a") + "</robot>"),
               Equals("r.urdf:6: robot/joint[1]: the joints form a loop: a chain has one root "
                      "link"));
    CHECK_THAT(import_error(ab + "<link name=\"c\">" + link + "</link>\n" + joint("j", "a", "b") +
                            "</robot>"),
               Equals("r.urdf:6: robot/link[3]: links 'a' and 'c' both have no parent: a chain "
                      "has one root"));
    CHECK_THAT(import_error(ab + "<link name=\"c\">" + link + "</link>\n" + "<link name=\"d\">" +
                            link + "</link>\n" + joint("j", "a", "b") + joint("k", "c", "d") +
                            joint("m", "d", "c") + "</robot>"),
               Equals("r.urdf:6: robot/link[3]: link 'c' is not on the chain from the root link "
                      "'a'"));
}

TEST_CASE("entity declarations and unknown entities are refused at their line", "[lines]") {
    const std::string robot = chain_urdf("0.1 0 0", "0 1 0", kLimit);
    const std::string body = robot.substr(robot.find('\n'));
    // tinyxml2 would keep "&h;" as the robot's name: the declaration is refused instead
    CHECK_THAT(import_error("<?xml version=\"1.0\"?>\n<!DOCTYPE robot [\n<!-- <!ENTITY -->\n"
                            "<!ENTITY h \"snake\">]>\n<robot name=\"&h;\">" +
                            body),
               Equals("r.urdf:4: entity declarations (<!ENTITY ...>) are not supported: write "
                      "the values out where they are used"));
    CHECK_THAT(import_error("<!DOCTYPE robot SYSTEM \"robot.dtd\">\n<!-- &h; -->\n<robot "
                            "name=\"&h;\">" +
                            body),
               Equals("r.urdf:3: unknown entity '&h;' (XML files here use only &lt; &gt; &amp; "
                      "&quot; &apos; and &#...; character references: write the value out)"));
    // tinyxml2 would read "&#65;a & b" as "Aa 5 b"
    CHECK_THAT(import_error("<robot name=\"&#65;a & b\">" + body),
               Equals("r.urdf:1: a '&' that starts no entity or character reference (write "
                      "&amp; for the character itself)"));
    // XML's own entities, character references and a DOCTYPE without declarations read as before
    const RobotSpec r = parse_urdf(
        "<!DOCTYPE robot [ <!-- ]> <!ENTITY --> ]>\n<robot name=\"&lt;&amp;h;&#65;&#x42;"
        " &amp; x\">" +
            body,
        "r.urdf");
    CHECK(r.name == "<&h;AB & x");
    // every gaitlab file is read the same way
    try {
        parse_robot("<gaitlab version=\"1\">\n<robot name=\"&nbsp;\"/></gaitlab>", "r.robot.xml");
        FAIL("no error");
    } catch (const FormatError& e) {
        CHECK_THAT(e.what(), Catch::StartsWith("r.robot.xml:2: unknown entity '&nbsp;'"));
    }
}

namespace {

// one link: a 0.1 m cube of 1 kg (its solid's moments 1/600 kg·m²) whose <inertial> has
// `inertial` (an <origin>, say) on line 3 and the <inertia> with `moments` on line 4
std::string link_urdf(const std::string& moments, const std::string& inertial = "",
                      const std::string& geometry = "<box size=\"0.1 0.1 0.1\"/>",
                      const std::string& at = "xyz=\"0 0 0\"") {
    return "<robot name=\"r\">\n<link name=\"a\"><collision><origin " + at + "/><geometry>" +
           geometry + "</geometry></collision>\n<inertial><mass value=\"1\"/>" + inertial +
           "\n<inertia " + moments + "/>\n</inertial></link>\n</robot>";
}

// kg·m², a tensor turned through frames: equal to rounding
bool same_moments(const Vec3& a, const Vec3& b) {
    const auto same = [](double x, double y) { return std::abs(x - y) <= 1e-12; };
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
}

Vec3 imported_inertia(const std::string& text) {
    const RobotSpec r = parse_urdf(text, "r.urdf");
    REQUIRE(r.bodies.size() == 1);
    REQUIRE(r.bodies[0].inertia);
    return *r.bodies[0].inertia;
}

// two coinciding bodies: link "a", the cube of link_urdf with its solid's inertia, and link "b",
// the same cube with `moments`, joined by a pitch joint through both centres
std::string pair_urdf(const std::string& moments) {
    const std::string cube =
        R"(<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>)";
    return "<robot name=\"r\">\n<link name=\"a\">" + cube +
           R"(<inertial><mass value="1"/></inertial></link>)" + "\n<link name=\"b\">" + cube +
           R"(<inertial><mass value="1"/><inertia )" + moments + "/></inertial></link>\n" +
           R"(<joint name="j" type="revolute"><parent link="a"/><child link="b"/>)" +
           R"(<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="0.5" velocity="5"/>)" +
           "</joint>\n</robot>";
}

}  // namespace

TEST_CASE("a link's diagonal inertia is its body's, and the body turns as it says") {
    const char* moments = R"(ixx="0.001" iyy="0.004" izz="0.0035" ixy="0" ixz="0" iyz="0")";
    CHECK(imported_inertia(link_urdf(moments)) == Vec3{0.001, 0.004, 0.0035});
    // the joint turns the two bodies against each other about their common centre, in a world
    // without gravity or floor: their angular momenta about y cancel, so their spins are in
    // the inverse ratio of their moments about y (the cube's 1/600 against b's 0.004)
    const RobotSpec robot = parse_urdf(pair_urdf(moments), "r.urdf");
    REQUIRE(robot.bodies[1].inertia);
    WorldSpec world;
    world.gravity = {0, 0, 0};
    world.floor.enabled = false;
    auto sine = std::make_shared<controllers::Sine>();
    world.robots.push_back({robot, {}, {{select_joints(robot, "all"), sine}}});
    Simulation sim(world);
    sim.run(0.3);
    const double a = sim.body(0, 0).angular_velocity.y, b = sim.body(0, 1).angular_velocity.y;
    CAPTURE(a, b);
    REQUIRE(std::abs(a) > 0.01);
    CHECK(-a / b == Approx(0.004 * 600).epsilon(1e-3));
}

TEST_CASE("an inertia is read about the body's own axes, through the frames that turn it") {
    // the inertial frame turned a quarter turn about z: its x is the body's y
    CHECK(same_moments(imported_inertia(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")",
                                                  R"(<origin rpy="0 0 1.5707963267948966"/>)")),
                       {0.004, 0.001, 0.0035}));
    // the geometry turned instead, the inertia in the link frame: the same body
    CHECK(same_moments(imported_inertia(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")", "",
                                                  "<box size=\"0.1 0.1 0.1\"/>",
                                                  R"(xyz="0 0 0" rpy="0 0 1.5707963267948966")")),
                       {0.004, 0.001, 0.0035}));
    // a URDF cylinder lies along z: its izz is about the body's axis (x)
    const Vec3 cylinder = imported_inertia(link_urdf(R"(ixx="0.004" iyy="0.004" izz="0.001")", "",
                                                     R"(<cylinder radius="0.05" length="0.2"/>)"));
    CHECK(same_moments(cylinder, {0.001, 0.004, 0.004}));
    // products that are rounding (an rpy of 1.5708) are dropped
    CHECK(same_moments(imported_inertia(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")",
                                                  R"(<origin rpy="0 0 1.5708"/>)")),
                       {0.004, 0.001, 0.0035}));
    // the solid's own moments (as an export writes them) leave the body's inertia the solid's
    const RobotSpec solid =
        parse_urdf(link_urdf(R"(ixx="0.0016666666666666668" iyy="0.0016666666666666668" )"
                             R"(izz="0.0016666666666666668")"),
                   "r.urdf");
    CHECK_FALSE(solid.bodies[0].inertia);
}

TEST_CASE("an origin turned more than ten turns is refused at its line", "[lines]") {
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")",
                                      R"(<origin rpy="0 1e300 0"/>)")),
               Catch::Matchers::Contains(
                   "origin: attribute 'rpy': angles in [-62.83185307179586, 62.83185307179586] rad "
                   "(ten turns) "
                   "expected, got 1e+300"));
}

TEST_CASE("an inertia gaitlab cannot give a body is refused at its line", "[lines]") {
    CHECK_THAT(import_error(link_urdf(R"(ixx="-0.001" iyy="0.004" izz="0.0035")")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: robot 'r' body 'a' "
                      "inertia x must be positive (got -0.001 kg·m²); or import the file with "
                      "each link a uniform solid of its shape and mass, its <inertia> not read "
                      "(gaitlab.robot.load_urdf(path, { inertia = \"shapes\" }))"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="nan" iyy="0.004" izz="0.0035")")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: attribute 'ixx': number "
                      "expected, got 'nan'"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004")")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: attribute 'izz' is "
                      "required (a number)"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.001" izz="0.0035")")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: robot 'r' body 'a' "
                      "inertia must have each moment at most the sum of the other two, as every "
                      "body's has (got 0.001 0.001 0.0035 kg·m²: z is 0.0035, the other two add "
                      "up to 0.002); or import the file with each link a uniform solid of its "
                      "shape and mass, its <inertia> not read (gaitlab.robot.load_urdf(path, { "
                      "inertia = \"shapes\" }))"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035" ixy="0.0005")")),
               Equals("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: link 'a': the inertia has "
                      "a product of 0.0005 kg·m² about its box's x and y axes (moments 0.001 "
                      "0.004 0.0035): its principal axes are turned about 9.22 degrees from the "
                      "box's, and gaitlab can only give a body principal moments about its "
                      "shape's own axes (products at most 0.001 of the largest moment are "
                      "dropped as rounding); or import the file with each link a uniform solid "
                      "of its shape and mass, its <inertia> not read "
                      "(gaitlab.robot.load_urdf(path, { inertia = \"shapes\" }))"));
    // a turned inertial frame whose axes are not the box's makes products too
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")",
                                      R"(<origin rpy="0 0 0.5"/>)")),
               Catch::StartsWith("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: link 'a': the "
                                 "inertia has a product of"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035" ixy="0.001")")),
               Catch::Contains("turned about 16.8 degrees"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035" ixq="0")")),
               Catch::StartsWith("r.urdf:4: robot/link[1]/inertial[1]/inertia[1]: unknown "
                                 "attribute 'ixq'"));
}

TEST_CASE("a centre of mass away from the shape's centre is read into its body") {
    const char* moments = R"(ixx="0.001" iyy="0.004" izz="0.0035")";
    const auto com = [](const std::string& text) {
        const RobotSpec r = parse_urdf(text, "r.urdf");
        REQUIRE(r.bodies.size() == 1);
        REQUIRE(r.bodies[0].center_of_mass);
        return *r.bodies[0].center_of_mass;
    };
    CHECK(com(link_urdf(moments, R"(<origin xyz="0.01 0 0"/>)")) == Vec3{0.01, 0, 0});
    // the inertia is about it, as URDF gives it
    CHECK(imported_inertia(link_urdf(moments, R"(<origin xyz="0.01 0 0"/>)")) ==
          Vec3{0.001, 0.004, 0.0035});
    // no <origin>: URDF's centre of mass is the link origin, here 0.05 m behind the box's
    // centre, on its -x face
    CHECK(com(link_urdf(moments, "", "<box size=\"0.1 0.1 0.1\"/>", R"(xyz="0.05 0 0")")) ==
          Vec3{-0.05, 0, 0});
    // in the body's own frame: a box turned a quarter turn about z has its x along the link's y
    const Vec3 turned =
        com(link_urdf(R"(ixx="0.004" iyy="0.001" izz="0.0035")", R"(<origin xyz="0.01 0 0"/>)",
                      "<box size=\"0.1 0.1 0.1\"/>", R"(rpy="0 0 1.5707963267948966")"));
    CHECK(turned.x == Approx(0).margin(1e-15));
    CHECK(turned.y == Approx(-0.01).epsilon(1e-12));
    // a cylinder's x is its axis, URDF's z
    const Vec3 along =
        com(link_urdf(R"(ixx="0.0035" iyy="0.0035" izz="0.001")", R"(<origin xyz="0 0 0.02"/>)",
                      "<cylinder radius=\"0.05\" length=\"0.15\"/>"));
    CHECK(along.x == Approx(0.02).epsilon(1e-12));
    CHECK(along.z == Approx(0).margin(1e-15));
    // within a millionth of the body it is the shape's centre: rounding in the file's digits
    const RobotSpec rounded =
        parse_urdf(link_urdf(moments, R"(<origin xyz="1e-8 0 0"/>)"), "r.urdf");
    CHECK_FALSE(rounded.bodies[0].center_of_mass);
}

TEST_CASE("a centre of mass outside the shape is refused at its line", "[lines]") {
    CHECK_THAT(
        import_error(
            link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")", R"(<origin xyz="0.06 0 0"/>)")),
        Equals("r.urdf:3: robot/link[1]/inertial[1]/origin[1]: robot 'r' body 'a' com must lie "
               "inside the box: each coordinate within half its size, ±0.05 ±0.05 ±0.05 m (got "
               "0.06 0 0 m) (link 'a': the <inertial> origin, xyz=\"0.06 0 0\", is 0.06 m from "
               "the centre of its box, its geometry's origin xyz=\"0 0 0\"); or import the file "
               "with each link a uniform solid of its shape and mass, its <inertia> not read "
               "(gaitlab.robot.load_urdf(path, { inertia = \"shapes\" }))"));
    // no <origin>: the link origin, 0.2 m from the box, named at the <inertial>
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")", "",
                                      "<box size=\"0.1 0.1 0.1\"/>", R"(xyz="0.2 0 0")")),
               Catch::StartsWith("r.urdf:3: robot/link[1]/inertial[1]: robot 'r' body 'a' com "
                                 "must lie inside the box"));
    // a cylinder's: within its radius of the axis
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.0035" iyy="0.0035" izz="0.001")",
                                      R"(<origin xyz="0.04 0.04 0"/>)",
                                      "<cylinder radius=\"0.05\" length=\"0.15\"/>")),
               Catch::StartsWith("r.urdf:3: robot/link[1]/inertial[1]/origin[1]: robot 'r' body "
                                 "'a' com must lie inside the cylinder: x within ±0.075 m (half "
                                 "its length), y and z within 0.05 m of its axis (its radius)"));
    CHECK_THAT(import_error(link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")",
                                      R"(<origin xyz="inf 0 0"/>)")),
               Equals("r.urdf:3: robot/link[1]/inertial[1]/origin: attribute 'xyz': three "
                      "numbers \"x y z\" expected, got 'inf 0 0'"));
}

TEST_CASE("a body's centre of mass exports and imports back, check_urdf passing") {
    RobotSpec robot = make_chain(ChainSpec{"offset", 2, Connection::pitch_pitch, [] {
                                               ModuleDef m = default_module_def();
                                               m.shape = Shape::cylinder;
                                               m.radius = 0.026;
                                               return m;
                                           }()});
    robot.chain.reset();
    robot.bodies[0].shape = Shape::box;
    robot.bodies[0].size = {0.036, 0.052, 0.052};
    robot.bodies[0].center_of_mass = Vec3{0.01, -0.005, 0.002};
    robot.bodies[0].inertia = Vec3{1e-5, 2e-5, 2.5e-5};
    // the turned cylinder: its centre of mass along its axis and off it, in its own frame
    robot.bodies[1].center_of_mass = Vec3{-0.02, 0.01, 0};
    robot.bodies[1].pose.orientation = Quat::from_axis_angle({0, 0, 1}, 0.3);
    robot.bodies[2].center_of_mass = Vec3{0, 0, -0.026};  // on the surface
    validate(robot);
    TempDir dir("urdf_com");
    write_urdf(dir.file("offset.urdf"), robot);
    const auto [status, out] = check_urdf(dir.file("offset.urdf"));
    INFO(out);
    CHECK(status == 0);
    const RobotSpec back = read_urdf(dir.file("offset.urdf"));
    check_same_robot(back, robot);
    // and again (to rounding: a turned link frame's last bits)
    write_urdf(dir.file("again.urdf"), back);
    check_same_robot(read_urdf(dir.file("again.urdf")), robot);
}

TEST_CASE("imported with inertia from shapes, each link is the uniform solid of its mass") {
    UrdfImport shapes;
    shapes.inertia_from_shapes = true;
    // a centre of mass outside the box, turned principal axes, impossible moments: none is read
    const std::string off_centre = link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035")", "",
                                             "<box size=\"0.1 0.1 0.1\"/>", R"(xyz="0.2 0 0")");
    const std::string turned = link_urdf(R"(ixx="0.001" iyy="0.004" izz="0.0035" ixy="0.001")");
    const std::string impossible = link_urdf(R"(ixx="-1" iyy="0.004" izz="0.0035")");
    const std::string mass_only =
        R"(<robot name="r"><link name="a"><collision><origin xyz="0.2 0 0"/><geometry>)"
        R"(<box size="0.1 0.1 0.1"/></geometry></collision><inertial><mass value="1"/>)"
        "</inertial></link></robot>";
    for (const std::string& text : {off_centre, turned, impossible}) {
        CHECK_THROWS_AS(parse_urdf(text, "r.urdf"), FormatError);
        const RobotSpec r = parse_urdf(text, "r.urdf", shapes);
        REQUIRE(r.bodies.size() == 1);
        CHECK_FALSE(r.bodies[0].inertia);
        CHECK_FALSE(r.bodies[0].center_of_mass);
        CHECK(r.bodies[0].mass == 1);
    }
    // the same body as a link with its mass alone, which both ways import alike
    const RobotSpec plain = parse_urdf(mass_only, "r.urdf");
    const RobotSpec from_shapes = parse_urdf(off_centre, "r.urdf", shapes);
    CHECK(format_robot(from_shapes) == format_robot(plain));
    CHECK(format_robot(parse_urdf(mass_only, "r.urdf", shapes)) == format_robot(plain));
    // what the option does not cover is still checked: a link without a mass
    CHECK_THROWS_WITH(parse_urdf(R"(<robot name="r"><link name="a"><collision><geometry>)"
                                 R"(<box size="0.1 0.1 0.1"/></geometry></collision></link>)"
                                 "</robot>",
                                 "r.urdf", shapes),
                      Catch::Contains("a link needs an <inertial> with a mass > 0"));
}

TEST_CASE("a body's given inertia exports and imports back, check_urdf passing") {
    RobotSpec robot = make_chain(ChainSpec{"given", 2, Connection::pitch_pitch, [] {
                                               ModuleDef m = default_module_def();
                                               m.shape = Shape::cylinder;
                                               m.radius = 0.026;
                                               return m;
                                           }()});
    robot.chain.reset();
    robot.bodies[0].shape = Shape::box;
    robot.bodies[0].size = {0.036, 0.052, 0.052};
    robot.bodies[0].inertia = Vec3{1e-5, 2e-5, 2.5e-5};
    robot.bodies[1].inertia = Vec3{1.5e-5, 3e-5, 2e-5};  // the cylinder: x along its axis
    robot.bodies[1].pose.orientation = Quat::from_axis_angle({0, 0, 1}, 0.3);
    validate(robot);
    TempDir dir("urdf_inertia");
    write_urdf(dir.file("given.urdf"), robot);
    const auto [status, out] = check_urdf(dir.file("given.urdf"));
    INFO(out);
    CHECK(status == 0);
    const RobotSpec back = read_urdf(dir.file("given.urdf"));
    check_same_robot(back, robot);
}
