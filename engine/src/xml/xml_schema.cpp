// The allow-lists of the XML readers, in one table (gaitlab/xml_schema.h).
#include "gaitlab/xml_schema.h"

#include "xml/xml_io.h"

namespace gaitlab {

namespace xml::attrs {

const std::vector<const char*> robot = {"name", "self_collision"};
const std::vector<const char*> chain = {"modules", "connection", "module"};
const std::vector<const char*> module = {"name",     "shape", "length",    "width",     "height",
                                         "radius",   "mass",  "axis",      "min",       "max",
                                         "friction", "kp",    "max_speed", "max_torque"};
const std::vector<const char*> body = {"name",        "shape",    "size",    "mass", "position",
                                       "orientation", "friction", "inertia", "com"};
const std::vector<const char*> joint = {"name", "role", "parent", "child",     "pivot",     "axis",
                                        "min",  "max",  "kp",     "max_speed", "max_torque"};
const std::vector<const char*> sensor_joint = {"kind", "name", "joint", "enabled"};
const std::vector<const char*> sensor_imu = {"kind", "name", "module", "half", "enabled"};
const std::vector<const char*> sensor_contact = {"kind", "name", "module", "enabled"};
const std::vector<const char*> sensor_range = {"kind",      "name",      "module", "half",
                                               "direction", "max_range", "enabled"};
const std::vector<const char*> sensor_position = {"kind", "name", "enabled"};

const std::vector<const char*> environment = {"gravity"};
const std::vector<const char*> floor = {"enabled", "friction", "rigid", "stiffness", "damping"};
const std::vector<const char*> box = {"size", "position", "yaw", "orientation", "mass", "friction"};
const std::vector<const char*> heightfield_source = {"image", "samples"};
const std::vector<const char*> place = {"robot", "position", "yaw", "orientation"};

const std::vector<const char*> simulation = {"name",
                                             "duration",
                                             "dt",
                                             "control_every",
                                             "solver_iterations",
                                             "seed",
                                             "on_controller_error",
                                             "solver",
                                             "newton_steps"};
const std::vector<const char*> simulation_environment = {"file"};
const std::vector<const char*> simulation_robot = {"file", "actuation"};
const std::vector<const char*> record = {"enabled", "dir", "every", "flush_seconds"};

const std::vector<const char*> actuation = {};
const std::vector<const char*> group = {"joints"};
const std::vector<const char*> controller = {"builtin", "file", "template"};

}  // namespace xml::attrs

namespace {

std::vector<std::string> strings(const std::vector<const char*>& names) {
    return {names.begin(), names.end()};
}

// the union of lists, each name once, in first-seen order
std::vector<std::string> joined(std::initializer_list<const std::vector<const char*>*> lists) {
    std::vector<std::string> out;
    for (const auto* list : lists) {
        for (const char* n : *list) {
            bool seen = false;
            for (const std::string& o : out)
                seen = seen || o == n;
            if (!seen) out.emplace_back(n);
        }
    }
    return out;
}

std::vector<XmlElementSchema> make_schema() {
    namespace a = xml::attrs;
    std::vector<XmlElementSchema> s = {
        {"robot", "robot", strings(a::robot)},
        {"robot", "chain", strings(a::chain)},
        {"robot", "module", strings(a::module)},
        {"robot", "body", strings(a::body)},
        {"robot", "joint", strings(a::joint)},
        {"robot", "sensor",
         joined({&a::sensor_joint, &a::sensor_imu, &a::sensor_contact, &a::sensor_range,
                 &a::sensor_position})},
        {"environment", "environment", strings(a::environment)},
        {"environment", "floor", strings(a::floor)},
        {"environment", "box", strings(a::box)},
    };
    for (XmlElementSchema& object : xml::environment_object_schema())
        s.push_back(std::move(object));
    s.push_back({"environment", "place", strings(a::place)});
    s.push_back({"simulation", "simulation", strings(a::simulation)});
    s.push_back({"simulation", "environment", strings(a::simulation_environment)});
    s.push_back({"simulation", "robot", strings(a::simulation_robot)});
    s.push_back({"simulation", "record", strings(a::record)});
    s.push_back({"actuation", "actuation", strings(a::actuation)});
    s.push_back({"actuation", "group", strings(a::group)});
    s.push_back({"actuation", "controller", strings(a::controller)});
    return s;
}

}  // namespace

const std::vector<XmlElementSchema>& xml_schema() {
    static const std::vector<XmlElementSchema> schema = make_schema();
    return schema;
}

}  // namespace gaitlab
