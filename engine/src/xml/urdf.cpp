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
#include <set>
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
    // from the entries of the rotation matrix
    const double r00 = 1 - 2 * (q.y * q.y + q.z * q.z), r10 = 2 * (q.x * q.y + q.w * q.z);
    const double r01 = 2 * (q.x * q.y - q.w * q.z), r11 = 1 - 2 * (q.x * q.x + q.z * q.z);
    const double r20 = 2 * (q.x * q.z - q.w * q.y), r21 = 2 * (q.y * q.z + q.w * q.x);
    const double r22 = 1 - 2 * (q.x * q.x + q.y * q.y);
    const double cos_pitch = std::hypot(r00, r10);
    const double pitch = std::atan2(-r20, cos_pitch);
    // pitched a quarter turn (a turned cylinder's geometry frame), roll and yaw turn about one
    // axis and the other entries are rounding: all of the turn is yaw
    if (cos_pitch < 1e-9) return {0, pitch, std::atan2(-r01, r11)};
    return {std::atan2(r21, r22), pitch, std::atan2(r10, r00)};
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
        const bool box = body.shape == Shape::box;
        // a cylinder's geometry frame has its axis along z
        const Quat turn = box ? body.pose.orientation : body.pose.orientation * kZToX;
        p.OpenElement("link");
        p.PushAttribute("name", body.name.c_str());
        p.OpenElement("inertial");
        // the centre of mass, in the link frame (parallel to the robot frame at rest)
        const Vec3 centre =
            body.center_of_mass ? at + body.pose.orientation.rotate(*body.center_of_mass) : at;
        origin(p, centre, turn);
        p.OpenElement("mass");
        p.PushAttribute("value", xml::format_number(body.mass).c_str());
        p.CloseElement();
        p.OpenElement("inertia");
        // the body's (given or its solid's) about the inertial frame's axes, which are the
        // geometry's: a cylinder's turn takes URDF's x to the body's -z and z to its x
        const Vec3 moments = body_inertia(body);
        const Vec3 inertia = box ? moments : Vec3{moments.z, moments.y, moments.x};
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
    std::optional<Vec3> inertia;         // about the body's axes, unless it is the solid's
    std::optional<Vec3> center_of_mass;  // in the body's frame, unless at its shape's centre
};

// URDF's <inertia>: the symmetric tensor about the axes of the <inertial> frame, kg·m²
struct UrdfInertia {
    double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
    double along(const Vec3& a, const Vec3& b) const {
        return a.x * (xx * b.x + xy * b.y + xz * b.z) + a.y * (xy * b.x + yy * b.y + yz * b.z) +
               a.z * (xz * b.x + yz * b.y + zz * b.z);
    }
};

// products of inertia up to this fraction of the largest moment, about the shape's axes, are
// rounding (an rpy of 1.5708 for pi/2 leaves 4e-6 of the moments' difference): dropping them
// changes the body's rotation by about as little
constexpr double kProductTolerance = 1e-3;

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
    for (double a : rpy) {
        if (!(std::fabs(a) <= deg_to_rad(kMaxAngleDegrees))) {
            o->fail(
                fmt::format("attribute 'rpy': angles in [-{}, {}] rad (ten turns) "
                            "expected, got {}",
                            deg_to_rad(kMaxAngleDegrees), deg_to_rad(kMaxAngleDegrees), a));
        }
    }
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

// ends each message about a link's <inertial> that a gaitlab body cannot hold
constexpr const char* kFromShapes =
    "; or import the file with each link a uniform solid of its shape and mass, its <inertia> "
    "not read (gaitlab.robot.load_urdf(path, { inertia = \"shapes\" }))";

// The <inertia> of link `name` as principal moments about its body's axes (`out` read
// whole), set in out.inertia unless it is the body's solid's; `inertial` is the <inertial>
// frame in the link frame. A tensor whose principal axes are not the shape's fails at `at`.
void read_inertia(const Element& at, const std::string& name, const UrdfInertia& tensor,
                  const Pose& inertial, UrdfLink& out) {
    // the body's axes in the <inertial> frame
    Vec3 axes[3];
    const Quat to_inertial = inertial.orientation.conjugate() * out.geometry.orientation;
    for (int k = 0; k < 3; ++k)
        axes[k] = to_inertial.rotate({k == 0 ? 1.0 : 0, k == 1 ? 1.0 : 0, k == 2 ? 1.0 : 0});
    const Vec3 moments{tensor.along(axes[0], axes[0]), tensor.along(axes[1], axes[1]),
                       tensor.along(axes[2], axes[2])};
    const double largest =
        std::max({std::abs(moments.x), std::abs(moments.y), std::abs(moments.z)});
    const std::pair<int, int> pairs[] = {{0, 1}, {0, 2}, {1, 2}};
    const char* const names[] = {"x", "y", "z"};
    const double diagonal[] = {moments.x, moments.y, moments.z};
    for (const auto& [a, b] : pairs) {
        const double product = tensor.along(axes[a], axes[b]);
        if (std::abs(product) <= kProductTolerance * largest) continue;
        // the turn about the third axis that would make this product 0 (a Jacobi rotation)
        const double turn =
            rad_to_deg(std::atan2(2 * std::abs(product), std::abs(diagonal[a] - diagonal[b])) / 2);
        const char* const shape = out.shape == Shape::box ? "box" : "cylinder";
        at.fail(fmt::format(
            "link '{}': the inertia has a product of {} kg·m² about its {}'s {} and {} axes "
            "(moments {} {} {}): its principal axes are turned about {:.3g} degrees from the "
            "{}'s, and gaitlab can only give a body principal moments about its shape's own "
            "axes (products at most {} of the largest moment are dropped as rounding){}",
            name, product, shape, names[a], names[b], moments.x, moments.y, moments.z, turn, shape,
            kProductTolerance, kFromShapes));
    }
    // the body's own solid's (as an export writes it, or to 7 digits) is left to the solid,
    // which the simulation computes to the same bits as for a link without an <inertia>
    BodySpec solid;
    solid.shape = out.shape;
    solid.size = out.size;
    solid.mass = out.mass;
    const Vec3 own = body_inertia(solid);
    const double scale = std::max({own.x, own.y, own.z});
    const Vec3 off = moments - own;
    if (std::max({std::abs(off.x), std::abs(off.y), std::abs(off.z)}) <= 1e-6 * scale) return;
    out.inertia = moments;
}

UrdfLink read_link(const Element& link, const std::string& robot, const std::string& link_name,
                   const UrdfImport& how) {
    UrdfLink out{link, link, Shape::box, {}, {}, 0, std::nullopt, std::nullopt};
    bool geometry = false;
    std::optional<Element> inertial, inertia;  // the <inertial>, its <inertia>
    std::optional<Element> centre;             // the <inertial>'s <origin>: its centre of mass
    Pose inertial_frame;
    UrdfInertia tensor;
    bool collision = false;
    for (const Element& k : link.children({"inertial", "visual", "collision"})) {
        const std::string kind = k.name();
        if (kind == "inertial") {
            // URDF has one of each; a second would be taken silently in place of the first
            if (inertial) k.fail("one <inertial> per link expected");
            inertial = k;
            std::set<std::string> parts;
            for (const Element& i : k.children({"origin", "mass", "inertia"})) {
                const std::string part = i.name();
                if (!parts.insert(part).second) {
                    i.fail(fmt::format("one <{}> per <inertial> expected", part));
                }
                if (part == "mass") out.mass = i.required_number("value");
                if (how.inertia_from_shapes) continue;
                if (part == "origin") {
                    inertial_frame = read_origin(k).first;
                    centre = i;
                }
                if (part == "inertia") {
                    i.allow({"ixx", "ixy", "ixz", "iyy", "iyz", "izz"});
                    tensor = {i.required_number("ixx"), i.required_number("iyy"),
                              i.required_number("izz"), i.number("ixy", 0),
                              i.number("ixz", 0),       i.number("iyz", 0)};
                    inertia = i;
                }
            }
            continue;
        }
        // the collision shape is the body; a visual one serves when there is no collision
        if (kind == "collision") {
            if (collision) {
                k.fail(
                    "one <collision> per link expected: a link becomes one body, one box or "
                    "cylinder");
            }
            collision = true;
        }
        if (geometry && kind == "visual") continue;
        bool shaped = false;
        for (const Element& g : k.children({"origin", "geometry", "material"})) {
            if (std::string(g.name()) != "geometry") continue;
            for (const Element& shape : g.children({"box", "cylinder", "sphere", "mesh"})) {
                if (shaped) shape.fail(fmt::format("one shape per <{}> expected", kind));
                shaped = true;
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
    // an <inertial> with only a mass is the uniform solid's, its centre of mass the shape's
    // centre; one that places its centre of mass (at the link origin without an <origin>)
    // elsewhere gives the body that centre of mass, in the body's own frame
    if (inertia || centre) {
        const Vec3 offset = inertial_frame.position - out.geometry.position;
        const double longest = std::max({out.size.x, out.size.y, out.size.z});
        // a millionth of the body: rounding in the file's digits, the shape's centre (whose
        // body moves to the bit as one without a centre of mass)
        if (offset.norm() > 1e-6 * longest) {
            out.center_of_mass = out.geometry.orientation.conjugate().rotate(offset);
            probe.center_of_mass = out.center_of_mass;
            const Element& at = centre ? *centre : *inertial;
            at.check([&] {
                try {
                    validate_body(robot, probe);
                } catch (const SpecError& e) {
                    throw SpecError(fmt::format(
                        "{} (link '{}': the <inertial> origin, xyz=\"{}\", is {:.6g} m from the "
                        "centre of its {}, its geometry's origin xyz=\"{}\"){}",
                        e.what(), link_name, numbers3(inertial_frame.position), offset.norm(),
                        out.shape == Shape::box ? "box" : "cylinder",
                        numbers3(out.geometry.position), kFromShapes));
                }
            });
        }
    }
    if (inertia) {
        read_inertia(*inertia, link_name, tensor, inertial_frame, out);
        probe.inertia = out.inertia;
        inertia->check([&] {
            try {
                validate_body(robot, probe);
            } catch (const SpecError& e) {
                throw SpecError(e.what() + std::string(kFromShapes));
            }
        });
    }
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
RobotSpec parse_urdf(std::string_view text, const std::string& file, const UrdfImport& how) {
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
            links.emplace(name, read_link(k, robot.name, name, how));
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
        b.inertia = link.inertia;
        b.center_of_mass = link.center_of_mass;
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

RobotSpec read_urdf(const std::string& path, const UrdfImport& how) {
    return parse_urdf(xml::read_text(path), path, how);
}

}  // namespace gaitlab
