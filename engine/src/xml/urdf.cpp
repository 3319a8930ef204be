// URDF export and import (see gaitlab/urdf.h). Link frames are parallel to the robot frame at
// rest: the root link's at its body's centre, every other link's at the pivot of the joint
// that carries it, so joint origins are pure translations and URDF's rule that a child link's
// frame is its joint's frame holds.
#include "gaitlab/urdf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gaitlab/files.h"
#include "gaitlab/xml.h"
#include "xml/xml_io.h"

namespace gaitlab {

namespace {

using xml::Element;

// URDF's rpy: fixed-axis roll about x, then pitch about y, then yaw about z
Quat from_rpy(double r, double p, double y) {
    return Quat::from_axis_angle({0, 0, 1}, y) * Quat::from_axis_angle({0, 1, 0}, p) *
           Quat::from_axis_angle({1, 0, 0}, r);
}

Vec3 to_rpy(const Quat& q) {
    const double sinp = 2 * (q.w * q.y - q.z * q.x);
    return {std::atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y)),
            std::abs(sinp) >= 1 ? std::copysign(kPi / 2, sinp) : std::asin(sinp),
            std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))};
}

std::string numbers3(const Vec3& v) {
    return fmt::format("{} {} {}", xml::format_number(v.x), xml::format_number(v.y),
                       xml::format_number(v.z));
}

void origin(tinyxml2::XMLPrinter& p, const Vec3& xyz, const Quat& q) {
    p.OpenElement("origin");
    p.PushAttribute("xyz", numbers3(xyz).c_str());
    p.PushAttribute("rpy", numbers3(to_rpy(q)).c_str());
    p.CloseElement();
}

// URDF cylinders lie along their frame's z, gaitlab's along the body's x: turning by +90°
// about y takes z to x
const Quat kZToX = Quat::from_axis_angle({0, 1, 0}, kPi / 2);

void geometry(tinyxml2::XMLPrinter& p, const BodySpec& body) {
    p.OpenElement("geometry");
    if (body.shape == Shape::box) {
        p.OpenElement("box");
        p.PushAttribute("size", numbers3(body.size).c_str());
    } else {
        p.OpenElement("cylinder");
        p.PushAttribute("radius", xml::format_number(body.size.y / 2).c_str());
        p.PushAttribute("length", xml::format_number(body.size.x).c_str());
    }
    p.CloseElement();
    p.CloseElement();
}

// the joint that carries each body (-1 for the root); SpecError unless the robot is a tree
std::vector<int> carriers(const RobotSpec& robot) {
    std::vector<int> by(robot.bodies.size(), -1);
    for (size_t j = 0; j < robot.joints.size(); ++j) {
        const int child = robot.joints[j].child;
        if (by[static_cast<size_t>(child)] >= 0) {
            throw SpecError(fmt::format(
                "robot '{}' is not a tree: body '{}' hangs from two joints (URDF needs a tree)",
                robot.name, robot.bodies[static_cast<size_t>(child)].name));
        }
        by[static_cast<size_t>(child)] = static_cast<int>(j);
    }
    std::vector<std::string> roots;
    for (size_t b = 0; b < by.size(); ++b)
        if (by[b] < 0) roots.push_back("'" + robot.bodies[b].name + "'");
    if (roots.empty()) {
        // every body hangs from a joint: the joints make a loop (a joined to b and b to a)
        throw SpecError(
            fmt::format("robot '{}' has a loop of joints: every body hangs from one, "
                        "so none is the root (URDF needs a tree)",
                        robot.name));
    }
    if (roots.size() > 1) {
        throw SpecError(
            fmt::format("robot '{}' is not connected: bodies {} hang from no joint "
                        "(URDF needs a single root body)",
                        robot.name, fmt::join(roots, ", ")));
    }
    return by;
}

}  // namespace

std::string format_urdf(const RobotSpec& robot) {
    validate(robot);
    const std::vector<int> carrier = carriers(robot);
    const auto link_origin = [&](size_t b) {
        return carrier[b] < 0 ? robot.bodies[b].pose.position
                              : robot.joints[static_cast<size_t>(carrier[b])].pivot;
    };
    tinyxml2::XMLPrinter p(nullptr, false, 0);
    p.PushHeader(false, true);
    p.PushComment(" written by gaitlab: one link per body, one revolute joint per joint ");
    p.OpenElement("robot");
    p.PushAttribute("name", robot.name.c_str());
    for (size_t b = 0; b < robot.bodies.size(); ++b) {
        const BodySpec& body = robot.bodies[b];
        const Vec3 at = body.pose.position - link_origin(b);
        const Vec3& s = body.size;
        const bool box = body.shape == Shape::box;
        // a cylinder's geometry frame has its axis along z
        const Quat turn = box ? body.pose.orientation : body.pose.orientation * kZToX;
        p.OpenElement("link");
        p.PushAttribute("name", body.name.c_str());
        p.OpenElement("inertial");
        origin(p, at, turn);
        p.OpenElement("mass");
        p.PushAttribute("value", xml::format_number(body.mass).c_str());
        p.CloseElement();
        p.OpenElement("inertia");
        const double m = body.mass / 12;
        const double r = s.y / 2;
        // solid box, or solid cylinder about its own (z) axis
        const Vec3 inertia = box ? Vec3{m * (s.y * s.y + s.z * s.z), m * (s.x * s.x + s.z * s.z),
                                        m * (s.x * s.x + s.y * s.y)}
                                 : Vec3{m * (3 * r * r + s.x * s.x), m * (3 * r * r + s.x * s.x),
                                        body.mass * r * r / 2};
        p.PushAttribute("ixx", xml::format_number(inertia.x).c_str());
        p.PushAttribute("ixy", "0");
        p.PushAttribute("ixz", "0");
        p.PushAttribute("iyy", xml::format_number(inertia.y).c_str());
        p.PushAttribute("iyz", "0");
        p.PushAttribute("izz", xml::format_number(inertia.z).c_str());
        p.CloseElement();
        p.CloseElement();
        for (const char* kind : {"visual", "collision"}) {
            p.OpenElement(kind);
            origin(p, at, turn);
            geometry(p, body);
            p.CloseElement();
        }
        p.CloseElement();
    }
    for (size_t j = 0; j < robot.joints.size(); ++j) {
        const JointSpec& joint = robot.joints[j];
        const size_t parent = static_cast<size_t>(joint.parent);
        p.OpenElement("joint");
        p.PushAttribute("name", joint.name.c_str());
        p.PushAttribute("type", "revolute");
        origin(p, joint.pivot - link_origin(parent), Quat{});
        p.OpenElement("parent");
        p.PushAttribute("link", robot.bodies[parent].name.c_str());
        p.CloseElement();
        p.OpenElement("child");
        p.PushAttribute("link", robot.bodies[static_cast<size_t>(joint.child)].name.c_str());
        p.CloseElement();
        p.OpenElement("axis");
        p.PushAttribute("xyz", numbers3(joint.axis).c_str());
        p.CloseElement();
        p.OpenElement("limit");
        p.PushAttribute("lower", xml::format_number(joint.min_angle).c_str());
        p.PushAttribute("upper", xml::format_number(joint.max_angle).c_str());
        p.PushAttribute("effort", xml::format_number(joint.servo.max_torque).c_str());
        p.PushAttribute("velocity", xml::format_number(joint.servo.max_speed).c_str());
        p.CloseElement();
        p.CloseElement();
    }
    p.CloseElement();
    return std::string(p.CStr(), static_cast<size_t>(p.CStrSize() - 1));
}

void write_urdf(const std::string& path, const RobotSpec& robot) {
    write_file_atomic(path, format_urdf(robot), MissingFolders::create);
}

namespace {

struct UrdfLink {
    Element element;    // the <link>
    Element placed_by;  // the <origin> that places its body in the link frame (or the <link>)
    Shape shape = Shape::box;
    Pose geometry;  // of the body (x along a cylinder's axis), in the link frame
    Vec3 size;
    double mass = 0;
};

struct UrdfJoint {
    Element element;    // the <joint>
    Element placed_by;  // its <origin> (or the <joint>)
    std::string name;
    std::string parent, child;
    Pose origin;  // of the joint (child link) frame in the parent link frame
    Vec3 axis{1, 0, 0};
    double lower = 0, upper = 0, effort = 0, velocity = 0;
};

// the <origin> of `e` (identity if none) and the element that gave it
std::pair<Pose, Element> read_origin(const Element& e) {
    const std::optional<Element> o = e.child("origin");
    if (!o) return {Pose{}, e};
    o->allow({"xyz", "rpy"});
    const std::vector<double> rpy = o->numbers("rpy", 3, {0, 0, 0});
    return {Pose{o->vec3("xyz", {}), from_rpy(rpy[0], rpy[1], rpy[2])}, *o};
}

// A joint that passes validate_joint, so that the values one element gives can be checked
// alone and an error named at that element: -1 to 1 rad, y1's servo.
JointSpec probe_joint(const std::string& name) {
    JointSpec j;
    j.name = name;
    j.axis = {1, 0, 0};
    j.min_angle = -1;
    j.max_angle = 1;
    return j;
}

// validate_joint's SpecError for `joint`, named at `at`
void check_joint(const Element& at, const std::string& robot, const JointSpec& joint) {
    RobotSpec r;
    r.name = robot;
    r.bodies.resize(2);  // the probe joins bodies 0 and 1
    at.check([&] { validate_joint(r, joint); });
}

UrdfLink read_link(const Element& link, const std::string& robot, const std::string& link_name) {
    UrdfLink out{link, link, Shape::box, {}, {}, 0};
    bool geometry = false;
    for (const Element& k : link.children({"inertial", "visual", "collision"})) {
        const std::string kind = k.name();
        if (kind == "inertial") {
            for (const Element& i : k.children({"origin", "mass", "inertia"})) {
                if (std::string(i.name()) == "mass") out.mass = i.required_number("value");
            }
            continue;
        }
        // the collision shape is the body; a visual one serves when there is no collision
        if (geometry && kind == "visual") continue;
        for (const Element& g : k.children({"origin", "geometry", "material"})) {
            if (std::string(g.name()) != "geometry") continue;
            for (const Element& shape : g.children({"box", "cylinder", "sphere", "mesh"})) {
                const std::string name = shape.name();
                auto [pose, from] = read_origin(k);
                out.geometry = pose;
                out.placed_by = from;
                if (name == "box") {
                    if (!shape.has("size")) shape.fail("attribute 'size' is required");
                    out.shape = Shape::box;
                    out.size = shape.vec3("size", {});
                } else if (name == "cylinder") {
                    const double r = shape.required_number("radius");
                    out.shape = Shape::cylinder;
                    out.size = {shape.required_number("length"), 2 * r, 2 * r};
                    // back from URDF's z axis to gaitlab's x
                    out.geometry.orientation = out.geometry.orientation * kZToX.conjugate();
                } else {
                    shape.fail(fmt::format(
                        "only box and cylinder geometry can be imported (got <{}>)", name));
                }
                geometry = true;
            }
        }
    }
    if (!geometry) link.fail("a link needs a box or a cylinder in <collision> or <visual>");
    if (!(out.mass > 0)) link.fail("a link needs an <inertial> with a mass > 0");
    // the body it becomes, checked here so its errors name the link's line
    BodySpec probe;
    probe.name = link_name;
    probe.shape = out.shape;
    probe.size = out.size;
    probe.mass = out.mass;
    link.check([&] { validate_body(robot, probe); });
    return out;
}

UrdfJoint read_joint(const Element& e, const std::string& robot) {
    UrdfJoint j{e, e, e.required_string("name"), {}, {}, {}, {1, 0, 0}, 0, 0, 0, 0};
    check_joint(e, robot, probe_joint(j.name));
    const std::string type = e.required_string("type");
    if (type != "revolute") {
        e.fail(fmt::format("only revolute joints can be imported (got type '{}')", type));
    }
    std::tie(j.origin, j.placed_by) = read_origin(e);
    bool limit = false;
    for (const Element& k : e.children({"origin", "parent", "child", "axis", "limit", "dynamics",
                                        "safety_controller", "calibration", "mimic"})) {
        const std::string kind = k.name();
        if (kind == "parent") j.parent = k.required_string("link");
        if (kind == "child") j.child = k.required_string("link");
        if (kind == "axis") {
            const Vec3 a = k.vec3("xyz", {1, 0, 0});
            // scaled by its largest component first, so that neither 1e300 nor 1e-320 fails
            const double big = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)});
            if (!(big > 0)) k.fail("attribute 'xyz': a non-zero axis expected");
            const Vec3 s{a.x / big, a.y / big, a.z / big};
            j.axis = s * (1 / s.norm());
            JointSpec probe = probe_joint(j.name);
            probe.axis = j.axis;
            check_joint(k, robot, probe);
        }
        if (kind == "limit") {
            limit = true;
            j.lower = k.required_number("lower");
            j.upper = k.required_number("upper");
            j.effort = k.required_number("effort");
            j.velocity = k.required_number("velocity");
            JointSpec probe = probe_joint(j.name);
            probe.min_angle = j.lower;
            probe.max_angle = j.upper;
            probe.servo.max_torque = j.effort;
            probe.servo.max_speed = j.velocity;
            check_joint(k, robot, probe);
        }
    }
    if (j.parent.empty() || j.child.empty()) e.fail("a joint needs <parent link> and <child link>");
    if (j.parent == j.child) {
        e.fail(
            fmt::format("a joint must join two different links (parent and child are both "
                        "'{}')",
                        j.parent));
    }
    if (!limit) e.fail("a revolute joint needs a <limit lower upper effort velocity>");
    return j;
}

Pose compose(const Pose& a, const Pose& b) {
    return {a.apply(b.position), a.orientation * b.orientation};
}

}  // namespace

// Every value of the robot is checked at the element that gave it: a link's name, size and mass
// at the <link>, a joint's name at the <joint>, its axis at <axis>, range and servo at <limit>
// as they are read; positions, which add up along the chain, at the <origin> that takes a pivot
// or a body out of range as the chain is walked; what the final shift of the robot onto the
// floor takes out of range at the <link> or <joint>.
RobotSpec parse_urdf(std::string_view text, const std::string& file) {
    const auto doc = xml::Document::foreign(text, file, "robot");
    const Element root = doc->root();
    RobotSpec robot;
    robot.name = root.string("name", "robot");
    std::map<std::string, UrdfLink> links;
    std::vector<std::string> link_order;
    std::vector<UrdfJoint> joints;                // in file order
    std::map<std::string, size_t> by_child;       // the joint that carries each link
    std::map<std::string, std::string> child_of;  // a link's one child link
    std::map<std::string, int> joint_names;
    for (const Element& k :
         root.children({"link", "joint", "material", "gazebo", "transmission"})) {
        const std::string kind = k.name();
        if (kind == "link") {
            const std::string name = k.required_string("name");
            if (links.count(name)) k.fail(fmt::format("a second link named '{}'", name));
            if (links.size() >= static_cast<size_t>(kMaxRobotBodies)) {
                k.fail(fmt::format("a robot has at most {} links", kMaxRobotBodies));
            }
            links.emplace(name, read_link(k, robot.name, name));
            link_order.push_back(name);
        } else if (kind == "joint") {
            UrdfJoint j = read_joint(k, robot.name);
            if (joint_names[j.name]++) k.fail(fmt::format("a second joint named '{}'", j.name));
            if (by_child.count(j.child)) {
                k.fail(fmt::format("link '{}' hangs from two joints", j.child));
            }
            if (child_of.count(j.parent)) {
                k.fail(
                    fmt::format("link '{}' has two child links: only serial chains can be "
                                "imported",
                                j.parent));
            }
            child_of[j.parent] = j.child;
            by_child[j.child] = joints.size();
            joints.push_back(std::move(j));
        }
    }
    if (links.empty()) root.fail("a robot needs at least one <link>");
    for (const UrdfJoint& j : joints) {
        for (const std::string& l : {j.parent, j.child}) {
            if (!links.count(l))
                j.element.fail(fmt::format("joint '{}' names no link '{}'", j.name, l));
        }
    }
    std::string first;
    for (const std::string& l : link_order) {
        if (!by_child.count(l)) {
            if (!first.empty()) {
                links.at(l).element.fail(
                    fmt::format("links '{}' and '{}' both have no parent: a chain has one "
                                "root",
                                first, l));
            }
            first = l;
        }
    }
    if (first.empty()) {
        // every link hangs from a joint, so every joint is on a loop: name the first
        joints.front().element.fail("the joints form a loop: a chain has one root link");
    }
    // walk the chain from the root, placing every link frame in the robot frame
    Pose frame;
    std::vector<const UrdfLink*> link_of;    // by body
    std::vector<const UrdfJoint*> joint_of;  // by joint
    for (std::string l = first;;) {
        const UrdfLink& link = links.at(l);
        BodySpec b;
        b.name = l;
        b.shape = link.shape;
        b.size = link.size;
        b.mass = link.mass;
        b.pose = compose(frame, link.geometry);
        // the frame is in range (its joint's pivot was checked): the body's own origin is not
        link.placed_by.check([&] { validate_body(robot.name, b); });
        robot.bodies.push_back(b);
        link_of.push_back(&link);
        const auto next = child_of.find(l);
        if (next == child_of.end()) break;
        const UrdfJoint& j = joints[by_child.at(next->second)];
        frame = compose(frame, j.origin);
        JointSpec js;
        js.name = j.name;
        js.parent = static_cast<int>(robot.bodies.size()) - 1;
        js.child = js.parent + 1;
        js.pivot = frame.position;
        js.axis = frame.orientation.rotate(j.axis);
        // the role follows the axis's largest component: x roll, y pitch, z yaw
        const Vec3 a{std::abs(js.axis.x), std::abs(js.axis.y), std::abs(js.axis.z)};
        js.role = a.x > a.y && a.x > a.z ? JointRole::roll
                  : a.z > a.y            ? JointRole::yaw
                                         : JointRole::pitch;
        js.min_angle = j.lower;
        js.max_angle = j.upper;
        js.servo.max_torque = j.effort;
        js.servo.max_speed = j.velocity;
        JointSpec probe = probe_joint(j.name);
        probe.pivot = js.pivot;
        check_joint(j.placed_by, robot.name, probe);
        robot.joints.push_back(js);
        joint_of.push_back(&j);
        l = next->second;
    }
    if (robot.bodies.size() != links.size()) {
        for (const std::string& l : link_order) {
            if (std::none_of(robot.bodies.begin(), robot.bodies.end(),
                             [&](const BodySpec& b) { return b.name == l; })) {
                links.at(l).element.fail(
                    fmt::format("link '{}' is not on the chain from the root link '{}'", l, first));
            }
        }
    }
    // gaitlab's robot frame: the rearmost point at x = 0, the lowest on the floor (z = 0)
    Vec3 low{std::numeric_limits<double>::infinity(), 0, std::numeric_limits<double>::infinity()};
    for (const BodySpec& b : robot.bodies) {
        for (int c = 0; c < 8; ++c) {
            const Vec3 corner =
                b.pose.apply({(c & 1 ? 0.5 : -0.5) * b.size.x, (c & 2 ? 0.5 : -0.5) * b.size.y,
                              (c & 4 ? 0.5 : -0.5) * b.size.z});
            low.x = std::min(low.x, corner.x);
            low.z = std::min(low.z, corner.z);
        }
    }
    for (BodySpec& b : robot.bodies)
        b.pose.position = b.pose.position - low;
    for (JointSpec& j : robot.joints)
        j.pivot = j.pivot - low;
    for (size_t i = 0; i < robot.bodies.size(); ++i)
        link_of[i]->element.check([&] { validate_body(robot.name, robot.bodies[i]); });
    for (size_t i = 0; i < robot.joints.size(); ++i)
        joint_of[i]->element.check([&] { validate_joint(robot, robot.joints[i]); });
    // what is left is the robot's own: its name
    root.check([&] { validate(robot); });
    return robot;
}

RobotSpec read_urdf(const std::string& path) {
    return parse_urdf(xml::read_text(path), path);
}

}  // namespace gaitlab
