// Robot files: a chain (modules, connection, module type) or, for any other robot, every body
// and joint. See docs/formats.md.
#include <map>

#include <fmt/format.h>

#include "gaitlab/checked.h"
#include "gaitlab/files.h"
#include "gaitlab/suggest.h"
#include "gaitlab/xml.h"
#include "xml/xml_io.h"

namespace gaitlab {

namespace {

using xml::Element;

// the module library by name (the default module is y1)
ModuleDef library_module(const Element& e, const std::string& name) {
    ModuleDef m;
    e.check([&] { m = builtin_module(name); });
    return m;
}

Shape parse_shape(const Element& e, Shape fallback) {
    const std::string s = e.string("shape", to_string(fallback));
    if (s == "box") return Shape::box;
    if (s == "cylinder") return Shape::cylinder;
    e.fail(fmt::format("attribute 'shape': 'box' or 'cylinder' expected, got '{}'", s));
}

ModuleDef read_module(const Element& e, ModuleDef m) {
    e.allow(xml::attrs::module);
    e.children({});
    m.name = e.string("name", m.name);
    m.shape = parse_shape(e, m.shape);
    m.length = e.number("length", m.length);
    m.width = e.number("width", m.width);
    m.height = e.number("height", m.height);
    m.radius = e.number("radius", m.radius);
    m.mass = e.number("mass", m.mass);
    const std::string axis = e.string("axis", to_string(m.axis));
    if (axis == "bend") {
        m.axis = JointAxis::bend;
    } else if (axis == "twist") {
        m.axis = JointAxis::twist;
    } else {
        e.fail(fmt::format("attribute 'axis': 'bend' or 'twist' expected, got '{}'", axis));
    }
    m.min_angle = e.angle("min", m.min_angle);
    m.max_angle = e.angle("max", m.max_angle);
    m.friction = e.number("friction", m.friction);
    m.servo.kp = e.number("kp", m.servo.kp);
    m.servo.max_speed = e.number("max_speed", m.servo.max_speed);
    m.servo.max_torque = e.number("max_torque", m.servo.max_torque);
    return m;
}

RobotSpec read_chain(const Element& e, const std::string& name) {
    e.allow(xml::attrs::chain);
    ChainSpec chain;
    chain.name = name;
    if (!e.has("modules")) e.fail("attribute 'modules' is required (the number of modules)");
    const long long n = e.integer("modules", 1);
    e.check([&] { chain.modules = checked_int("modules", n, 1, kMaxModules); });
    e.check([&] { chain.connection = parse_connection(e.string("connection", "pitch-pitch")); });
    chain.module = library_module(e, e.string("module", "y1"));
    const std::vector<Element> kids = e.children({"module"});
    if (kids.size() > 1) kids[1].fail("one <module> per chain expected");
    if (!kids.empty()) chain.module = read_module(kids[0], chain.module);
    try {
        return make_chain(chain);
    } catch (const SpecError& err) {
        (kids.empty() ? e : kids[0]).fail(err.what());
    }
}

// the body named by attribute `attr`, among those read so far (`index`: name -> index)
int body_index(const Element& e, const std::map<std::string, int>& index, const char* attr) {
    const std::string name = e.required_string(attr);
    const auto it = index.find(name);
    if (it != index.end()) return it->second;
    std::vector<std::string> names;
    for (const auto& [n, i] : index)
        names.push_back(n);
    e.fail(fmt::format("attribute '{}': no body '{}' above this joint{}", attr, name,
                       did_you_mean(name, names)));
}

JointRole parse_role(const Element& e) {
    const std::string role = e.string("role", "pitch");
    if (role == "pitch") return JointRole::pitch;
    if (role == "yaw") return JointRole::yaw;
    if (role == "roll") return JointRole::roll;
    e.fail(fmt::format("attribute 'role': 'pitch', 'yaw' or 'roll' expected, got '{}'", role));
}

// one <sensor>: the fields of its kind (module and joint numbered from 1, as users do)
SensorSpec read_sensor(const Element& e) {
    SensorSpec s;
    e.check([&] { s.kind = parse_sensor_kind(e.required_string("kind")); });
    switch (s.kind) {
        case SensorKind::joint:
            e.allow(xml::attrs::sensor_joint);
            break;
        case SensorKind::imu:
            e.allow(xml::attrs::sensor_imu);
            break;
        case SensorKind::contact:
            e.allow(xml::attrs::sensor_contact);
            break;
        case SensorKind::range:
            e.allow(xml::attrs::sensor_range);
            break;
        case SensorKind::position:
            e.allow(xml::attrs::sensor_position);
            break;
    }
    e.children({});
    s.name = e.string("name", "");
    // numbered from 1; beyond any robot's size they are refused before they can wrap into it
    // (validate_sensor then names the robot's own range)
    const long long module = e.integer("module", 1), joint = e.integer("joint", 1);
    e.check([&] {
        s.module = checked_int("module", module, 1, kMaxRobotBodies) - 1;
        s.joint = checked_int("joint", joint, 1, kMaxRobotBodies) - 1;
    });
    e.check([&] { s.half = parse_module_half(e.string("half", "head")); });
    s.direction = e.vec3("direction", s.direction);
    s.max_range = e.number("max_range", s.max_range);
    s.enabled = e.boolean("enabled", true);
    return s;
}

void write_sensor(xml::Writer& w, const SensorSpec& s) {
    w.open("sensor");
    w.attr("kind", to_string(s.kind));
    w.attr("name", sensor_name(s));
    switch (s.kind) {
        case SensorKind::joint:
            w.attr_int("joint", s.joint + 1);
            break;
        case SensorKind::imu:
            w.attr_int("module", s.module + 1);
            w.attr("half", to_string(s.half));
            break;
        case SensorKind::contact:
            w.attr_int("module", s.module + 1);
            break;
        case SensorKind::range:
            w.attr_int("module", s.module + 1);
            w.attr("half", to_string(s.half));
            w.attr("direction", s.direction);
            w.attr("max_range", s.max_range);
            break;
        case SensorKind::position:
            break;
    }
    if (!s.enabled) w.attr("enabled", false);
    w.close();
}

RobotSpec read_robot_element(const Element& root) {
    root.allow(xml::attrs::robot);
    const std::string name = root.string("name", "robot");
    const bool self_collision = root.boolean("self_collision", false);
    const std::vector<Element> kids = root.children({"chain", "body", "joint", "sensor"});
    RobotSpec robot;
    robot.name = name;
    std::map<std::string, int> body_names;  // name -> index, for joints and repeated names
    bool chain = false, parts = false;
    std::vector<std::pair<const Element*, SensorSpec>> sensors;
    for (const Element& k : kids) {
        const std::string kind = k.name();
        if (kind == "sensor") {
            if (sensors.size() >= static_cast<size_t>(kMaxSensors)) {
                k.fail(fmt::format("a robot has at most {} sensors", kMaxSensors));
            }
            sensors.emplace_back(&k, read_sensor(k));
            continue;
        }
        if (kind == "chain") {
            if (chain || parts) {
                k.fail("a robot is one <chain>, or <body> and <joint> elements (and <sensor>s)");
            }
            robot = read_chain(k, name);
            chain = true;
            continue;
        }
        if (chain) k.fail("a robot is one <chain>, or <body> and <joint> elements (and <sensor>s)");
        parts = true;
        if (kind == "body") {
            k.allow(xml::attrs::body);
            k.children({});
            if (robot.bodies.size() >= static_cast<size_t>(kMaxRobotBodies)) {
                k.fail(fmt::format("a robot has at most {} bodies", kMaxRobotBodies));
            }
            BodySpec b;
            b.name = k.required_string("name");
            if (body_names.count(b.name)) {
                k.fail(fmt::format("a second body named '{}'", b.name));
            }
            b.shape = parse_shape(k, Shape::box);
            if (!k.has("size")) k.fail("attribute 'size' is required (\"x y z\", m)");
            b.size = k.vec3("size", {});
            b.mass = k.required_number("mass");
            b.pose.position = k.vec3("position", {});
            b.pose.orientation = k.quat("orientation", {});
            b.friction = k.number("friction", 1.0);
            if (k.has("inertia")) b.inertia = k.vec3("inertia", {});
            if (k.has("com")) b.center_of_mass = k.vec3("com", {});
            // checked here, so its errors name its own line
            k.check([&] { validate_body(name, b); });
            body_names.emplace(b.name, static_cast<int>(robot.bodies.size()));
            robot.bodies.push_back(b);
        } else {
            k.allow(xml::attrs::joint);
            k.children({});
            if (robot.joints.size() >= static_cast<size_t>(kMaxRobotBodies)) {
                k.fail(fmt::format("a robot has at most {} joints", kMaxRobotBodies));
            }
            JointSpec j;
            j.name = k.required_string("name");
            j.role = parse_role(k);
            j.parent = body_index(k, body_names, "parent");
            j.child = body_index(k, body_names, "child");
            if (!k.has("pivot")) k.fail("attribute 'pivot' is required (\"x y z\", m)");
            j.pivot = k.vec3("pivot", {});
            if (!k.has("axis")) k.fail("attribute 'axis' is required (a unit vector \"x y z\")");
            j.axis = k.vec3("axis", {});
            const ModuleDef y1 = default_module_def();
            j.min_angle = k.angle("min", y1.min_angle);
            j.max_angle = k.angle("max", y1.max_angle);
            j.servo.kp = k.number("kp", y1.servo.kp);
            j.servo.max_speed = k.number("max_speed", y1.servo.max_speed);
            j.servo.max_torque = k.number("max_torque", y1.servo.max_torque);
            k.check([&] { validate_joint(robot, j); });
            robot.joints.push_back(j);
        }
    }
    if (!chain && !parts) root.fail("a robot needs a <chain>, or <body> and <joint> elements");
    robot.name = name;
    if (robot.chain) robot.chain->name = name;
    robot.self_collision = self_collision;
    // sensors name modules and joints, so they are checked once the robot is complete
    for (auto& read : sensors) {
        SensorSpec& sensor = read.second;
        read.first->check([&] { validate_sensor(robot, sensor); });
        if (sensor.name.empty()) sensor.name = default_sensor_name(sensor);
        robot.sensors.push_back(sensor);
    }
    root.check([&] { validate(robot); });
    return robot;
}

// the joint range and servo, as <module> and <joint> write them
void write_servo(xml::Writer& w, double min, double max, const ServoDef& servo) {
    w.angle("min", min);
    w.angle("max", max);
    w.attr("kp", servo.kp);
    w.attr("max_speed", servo.max_speed);
    w.attr("max_torque", servo.max_torque);
}

void write_module(xml::Writer& w, const ModuleDef& m) {
    w.open("module");
    w.attr("name", m.name);
    w.attr("shape", to_string(m.shape));
    w.attr("length", m.length);
    w.attr("width", m.width);
    w.attr("height", m.height);
    w.attr("radius", m.radius);
    w.attr("mass", m.mass);
    w.attr("axis", to_string(m.axis));
    w.attr("friction", m.friction);
    write_servo(w, m.min_angle, m.max_angle, m.servo);
    w.close();
}

// whether the robot is still exactly the chain it was built from
bool is_chain(const RobotSpec& robot) {
    if (!robot.chain) return false;
    ChainSpec c = *robot.chain;
    c.name = robot.name;
    const RobotSpec built = make_chain(c);
    return built.bodies == robot.bodies && built.joints == robot.joints;
}

}  // namespace

RobotSpec parse_robot(std::string_view text, const std::string& file) {
    const xml::Document doc(text, file, "robot");
    return read_robot_element(doc.root());
}

RobotSpec read_robot(const std::string& path) {
    return parse_robot(xml::read_text(path), path);
}

std::string format_robot(const RobotSpec& robot) {
    validate(robot);
    xml::Writer w;
    w.open("robot");
    w.attr("name", robot.name);
    if (robot.self_collision) w.attr("self_collision", true);
    if (is_chain(robot)) {
        const ChainSpec& c = *robot.chain;
        w.open("chain");
        w.attr_int("modules", c.modules);
        w.attr("connection", to_string(c.connection));
        // a module of the library by its name, any other with all its values
        bool library = false;
        for (const ModuleDef& m : builtin_modules())
            library = library || m == c.module;
        if (library) {
            w.attr("module", c.module.name);
        } else {
            write_module(w, c.module);
        }
        w.close();
    } else {
        for (const BodySpec& b : robot.bodies) {
            w.open("body");
            w.attr("name", b.name);
            if (b.shape != Shape::box) w.attr("shape", to_string(b.shape));
            w.attr("size", b.size);
            w.attr("mass", b.mass);
            w.attr("position", b.pose.position);
            if (!(b.pose.orientation == Quat{})) w.attr("orientation", b.pose.orientation);
            w.attr("friction", b.friction);
            if (b.inertia) w.attr("inertia", *b.inertia);
            if (b.center_of_mass) w.attr("com", *b.center_of_mass);
            w.close();
        }
        for (const JointSpec& j : robot.joints) {
            w.open("joint");
            w.attr("name", j.name);
            w.attr("role", to_string(j.role));
            w.attr("parent", robot.bodies[static_cast<size_t>(j.parent)].name);
            w.attr("child", robot.bodies[static_cast<size_t>(j.child)].name);
            w.attr("pivot", j.pivot);
            w.attr("axis", j.axis);
            write_servo(w, j.min_angle, j.max_angle, j.servo);
            w.close();
        }
    }
    for (const SensorSpec& sensor : robot.sensors)
        write_sensor(w, sensor);
    w.close();
    return w.text();
}

void write_robot(const std::string& path, const RobotSpec& robot) {
    write_file_atomic(path, format_robot(robot), MissingFolders::create);
}

}  // namespace gaitlab
