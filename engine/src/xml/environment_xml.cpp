// Environment files: gravity, the floor, objects, and where each robot is placed. See
// docs/formats.md.
#include <cmath>

#include <fmt/format.h>

#include "gaitlab/files.h"
#include "gaitlab/xml.h"
#include "xml_io.h"

namespace gaitlab {

namespace {

using xml::Element;

Quat yaw_quat(double rad) {
    return Quat::from_axis_angle({0, 0, 1}, rad);
}

// an orientation given as yaw (deg) or as a quaternion, not both
Quat read_orientation(const Element& e) {
    if (e.has("yaw") && e.has("orientation")) {
        e.fail("give 'yaw' or 'orientation', not both");
    }
    if (e.has("orientation")) return e.quat("orientation", {});
    return yaw_quat(e.angle("yaw", 0));
}

// a pure yaw is written as yaw (deg) when that reads back exactly, else as a quaternion
void write_orientation(xml::Writer& w, const Quat& q) {
    if (q == Quat{}) return;
    if (q.x == 0 && q.y == 0) {
        const double deg = xml::degrees_for(
            2 * std::atan2(q.z, q.w), [&q](double d) { return yaw_quat(deg_to_rad(d)) == q; });
        if (yaw_quat(deg_to_rad(deg)) == q) {
            w.attr("yaw", deg);
            return;
        }
    }
    w.attr("orientation", q);
}

EnvironmentSpec read_environment_element(const Element& root) {
    root.allow({"gravity"});
    EnvironmentSpec env;
    WorldSpec& world = env.world;
    world.gravity = root.vec3("gravity", world.gravity);
    bool floor_seen = false;
    for (const Element& k : root.children({"floor", "box", "place"})) {
        const std::string kind = k.name();
        k.children({});
        if (kind == "floor") {
            if (floor_seen) k.fail("one <floor> per environment expected");
            floor_seen = true;
            k.allow({"enabled", "friction"});
            world.floor.enabled = k.boolean("enabled", true);
            world.floor.friction = k.number("friction", world.floor.friction);
            WorldSpec probe;
            probe.floor = world.floor;
            k.check([&] { validate(probe); });
        } else if (kind == "box") {
            k.allow({"size", "position", "yaw", "orientation", "mass", "friction"});
            BoxSpec b;
            b.size = k.vec3("size", b.size);
            b.pose.position = k.vec3("position", {0, 0, b.size.z / 2});
            b.pose.orientation = read_orientation(k);
            b.mass = k.number("mass", 0);
            b.friction = k.number("friction", 1.0);
            world.boxes.push_back(b);
            WorldSpec probe;
            probe.boxes = world.boxes;
            k.check([&] { validate(probe); });
        } else {
            k.allow({"robot", "position", "yaw", "orientation"});
            Placement p;
            p.robot = k.required_string("robot");
            for (const Placement& other : env.placements) {
                if (other.robot == p.robot) {
                    k.fail(fmt::format("robot '{}' is placed twice", p.robot));
                }
            }
            p.pose.position = k.vec3("position", {});
            p.pose.orientation = read_orientation(k);
            env.placements.push_back(p);
        }
    }
    root.check([&] { validate(world); });
    return env;
}

}  // namespace

EnvironmentSpec parse_environment(std::string_view text, const std::string& file) {
    const xml::Document doc(text, file, "environment");
    return read_environment_element(doc.root());
}

EnvironmentSpec read_environment(const std::string& path) {
    return parse_environment(xml::read_text(path), path);
}

std::string format_environment(const EnvironmentSpec& env) {
    WorldSpec world = env.world;
    world.robots.clear();
    validate(world);
    xml::Writer w;
    w.open("environment");
    w.attr("gravity", world.gravity);
    w.open("floor");
    if (!world.floor.enabled) w.attr("enabled", false);
    w.attr("friction", world.floor.friction);
    w.close();
    for (const BoxSpec& b : world.boxes) {
        w.open("box");
        w.attr("size", b.size);
        w.attr("position", b.pose.position);
        write_orientation(w, b.pose.orientation);
        if (b.mass != 0) w.attr("mass", b.mass);
        w.attr("friction", b.friction);
        w.close();
    }
    for (const Placement& p : env.placements) {
        w.open("place");
        w.attr("robot", p.robot);
        w.attr("position", p.pose.position);
        write_orientation(w, p.pose.orientation);
        w.close();
    }
    w.close();
    return w.text();
}

void write_environment(const std::string& path, const EnvironmentSpec& env) {
    write_file_atomic(path, format_environment(env));
}

}  // namespace gaitlab
