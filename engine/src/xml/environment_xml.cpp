// Environment files: gravity, the floor, the objects of the world library, and where each robot
// is placed. See docs/formats.md. Each object kind lists its fields once (gaitlab/world_fields.h),
// in a function that both the reader and the writer walk, so the two cannot disagree.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "gaitlab/checked.h"
#include "gaitlab/files.h"
#include "gaitlab/geometry.h"
#include "gaitlab/robot.h"
#include "gaitlab/world_fields.h"
#include "gaitlab/xml.h"
#include "xml/xml_io.h"

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
    const double yaw = e.angle("yaw", 0);
    if (!(std::abs(yaw) <= deg_to_rad(kMaxAngleDegrees))) {
        e.fail(
            fmt::format("attribute 'yaw': an angle in [-{0}, {0}] degrees (ten turns) "
                        "expected, got {1}",
                        kMaxAngleDegrees, rad_to_deg(yaw)));
    }
    return yaw_quat(yaw);
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

// the three walks over an object's fields: collect the attribute names, read, write
struct Names {
    std::vector<const char*> names;
    template <class T>
    void number(const char* name, T&, const char*) {
        names.push_back(name);
    }
    template <class T>
    void vec3(const char* name, T&, const char*) {
        names.push_back(name);
    }
    template <class T>
    void angle(const char* name, T&) {
        names.push_back(name);
    }
    template <class T>
    void count(const char* name, T&, int, int) {
        names.push_back(name);
    }
    template <class T>
    void seed(const char* name, T&) {
        names.push_back(name);
    }
    template <class T>
    void flag(const char* name, T&) {
        names.push_back(name);
    }
};

struct Read {
    const Element& e;
    void number(const char* name, double& v, const char*) { v = e.number(name, v); }
    void vec3(const char* name, Vec3& v, const char*) { v = e.vec3(name, v); }
    void angle(const char* name, double& v) { v = e.angle(name, v); }
    // a count is checked against its range before it becomes an int: it never wraps
    void count(const char* name, int& v, int lo, int hi) {
        const long long n = e.integer(name, v);
        e.check([&] { v = checked_int(name, n, lo, hi); });
    }
    void seed(const char* name, std::uint64_t& v) {
        const long long n = e.integer(name, static_cast<long long>(v));
        if (n < 0) e.fail(fmt::format("attribute '{}': a non-negative integer expected", name));
        v = static_cast<std::uint64_t>(n);
    }
    void flag(const char* name, bool& v) { v = e.boolean(name, v); }
};

struct Write {
    xml::Writer& w;
    void number(const char* name, double v, const char*) { w.attr(name, v); }
    void vec3(const char* name, const Vec3& v, const char*) { w.attr(name, v); }
    void angle(const char* name, double v) { w.angle(name, v); }
    void count(const char* name, int v, int, int) { w.attr_int(name, v); }
    void seed(const char* name, std::uint64_t v) { w.attr_int(name, static_cast<long long>(v)); }
    void flag(const char* name, bool v) { w.attr(name, v); }
};

template <class S>
std::vector<const char*> names_of(const std::vector<const char*>& extra = {}) {
    Names n;
    S probe;
    world_object_fields(n, probe, static_cast<S*>(nullptr));
    n.names.insert(n.names.end(), extra.begin(), extra.end());
    return n.names;
}

// reads one object of kind S into `out`, checked as object number out.size()
template <class S>
void read_object(const Element& e, std::vector<S>& out) {
    e.allow(names_of<S>());
    e.children({});
    S s;
    Read r{e};
    world_object_fields(r, s, static_cast<S*>(nullptr));
    e.check([&] { validate(s, static_cast<int>(out.size()) + 1); });
    out.push_back(std::move(s));
}

template <class S>
void write_objects(xml::Writer& w, const char* element, const std::vector<S>& objects) {
    for (const S& s : objects) {
        w.open(element);
        Write wr{w};
        world_object_fields(wr, s, static_cast<S*>(nullptr));
        w.close();
    }
}

void read_heightfield(const Element& e, std::vector<HeightfieldSpec>& out) {
    e.allow(names_of<HeightfieldSpec>(xml::attrs::heightfield_source));
    HeightfieldSpec h;
    Read r{e};
    world_object_fields(r, h, static_cast<HeightfieldSpec*>(nullptr));
    const std::vector<Element> kids = e.children({"heights"});
    if (e.has("image") == (e.has("samples") || !kids.empty())) {
        e.fail("give 'image' (a PNG file) or 'samples' and <heights>, one of them");
    }
    if (e.has("image")) {
        // relative to the environment file, as every path in a file is
        h.image = resolve_path(e.file(), e.required_string("image"));
    } else {
        const std::vector<double> n = e.numbers("samples", 2, {});
        if (n.empty()) e.fail("attribute 'samples' is required (\"nx ny\") with <heights>");
        if (!(n[0] >= 2 && n[0] <= 4096 && n[1] >= 2 && n[1] <= 4096 && n[0] == std::floor(n[0]) &&
              n[1] == std::floor(n[1]))) {
            e.fail(fmt::format("attribute 'samples': two whole numbers in [2, 4096] expected"));
        }
        h.samples_x = static_cast<int>(n[0]);
        h.samples_y = static_cast<int>(n[1]);
        if (kids.size() != 1) e.fail("one <heights> expected (nx × ny heights in m)");
        std::istringstream in(kids[0].text());
        double z = 0;
        while (in >> z)
            h.heights.push_back(z);
        if (!in.eof()) kids[0].fail("numbers expected (heights in m)");
        const size_t want = static_cast<size_t>(h.samples_x) * static_cast<size_t>(h.samples_y);
        if (h.heights.size() != want) {
            kids[0].fail(fmt::format("{} heights expected ({} × {}), got {}", want, h.samples_x,
                                     h.samples_y, h.heights.size()));
        }
    }
    e.check([&] { validate(h, static_cast<int>(out.size()) + 1); });
    // an image is read now, as the Lua heightfield{ image = } reads it: a missing or broken one
    // is named with this file's line, not later by the simulation without a place
    if (!h.image.empty()) e.check([&] { height_grid(h, static_cast<int>(out.size()) + 1); });
    out.push_back(std::move(h));
}

void write_heightfields(xml::Writer& w, const std::vector<HeightfieldSpec>& all,
                        const std::string& file) {
    for (const HeightfieldSpec& h : all) {
        w.open("heightfield");
        Write wr{w};
        world_object_fields(wr, h, static_cast<HeightfieldSpec*>(nullptr));
        if (h.heights.empty()) {
            w.attr("image", file.empty() ? h.image : relative_path(h.image, file));
            w.close();
            continue;
        }
        w.attr("samples", fmt::format("{} {}", h.samples_x, h.samples_y));
        w.open("heights");
        // one row of x samples per line, from the −y edge
        std::string rows = "\n";
        for (int j = 0; j < h.samples_y; ++j) {
            for (int i = 0; i < h.samples_x; ++i) {
                rows += (i ? " " : "") +
                        xml::format_number(h.heights[static_cast<size_t>(j * h.samples_x + i)]);
            }
            rows += "\n";
        }
        w.text(rows);
        w.close();
        w.close();
    }
}

EnvironmentSpec read_environment_element(const Element& root) {
    root.allow(xml::attrs::environment);
    EnvironmentSpec env;
    WorldSpec& world = env.world;
    world.gravity = root.vec3("gravity", world.gravity);
    bool floor_seen = false;
    for (const Element& k : root.children({"floor", "box", "wall", "ramp", "stairs", "cylinder",
                                           "pipe", "rubble", "heightfield", "place"})) {
        const std::string kind = k.name();
        if (kind == "floor") {
            k.children({});
            if (floor_seen) k.fail("one <floor> per environment expected");
            floor_seen = true;
            k.allow(xml::attrs::floor);
            world.floor.enabled = k.boolean("enabled", true);
            world.floor.friction = k.number("friction", world.floor.friction);
            world.floor.rigid = k.boolean("rigid", false);
            if (k.has("stiffness")) world.floor.stiffness = k.number("stiffness", 0);
            if (k.has("damping")) world.floor.damping = k.number("damping", 0);
            WorldSpec probe;
            probe.floor = world.floor;
            k.check([&] { validate(probe); });
        } else if (kind == "box") {
            k.children({});
            k.allow(xml::attrs::box);
            BoxSpec b;
            b.size = k.vec3("size", b.size);
            b.pose.position = k.vec3("position", {0, 0, b.size.z / 2});
            b.pose.orientation = read_orientation(k);
            b.mass = k.number("mass", 0);
            b.friction = k.number("friction", 1.0);
            k.check([&] { validate(b, static_cast<int>(world.boxes.size()) + 1); });
            world.boxes.push_back(b);
        } else if (kind == "wall") {
            read_object(k, world.walls);
        } else if (kind == "ramp") {
            read_object(k, world.ramps);
        } else if (kind == "stairs") {
            read_object(k, world.stairs);
        } else if (kind == "cylinder") {
            read_object(k, world.cylinders);
        } else if (kind == "pipe") {
            read_object(k, world.pipes);
        } else if (kind == "rubble") {
            read_object(k, world.rubble);
        } else if (kind == "heightfield") {
            read_heightfield(k, world.heightfields);
        } else {
            k.children({});
            k.allow(xml::attrs::place);
            Placement p;
            p.line = k.line();
            p.robot = k.required_string("robot");
            k.check([&] { validate_name("robot name", p.robot); });
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

std::vector<XmlElementSchema> xml::environment_object_schema() {
    auto entry = [](const char* element, const std::vector<const char*>& names) {
        return XmlElementSchema{"environment", element, {names.begin(), names.end()}};
    };
    return {entry("wall", names_of<WallSpec>()),
            entry("ramp", names_of<RampSpec>()),
            entry("stairs", names_of<StairsSpec>()),
            entry("cylinder", names_of<CylinderSpec>()),
            entry("pipe", names_of<PipeSpec>()),
            entry("rubble", names_of<RubbleSpec>()),
            entry("heightfield", names_of<HeightfieldSpec>(xml::attrs::heightfield_source))};
}

std::string relative_path(const std::string& path, const std::string& from_file) {
    namespace fs = std::filesystem;
    if (path.empty()) return path;
    std::error_code ec;
    const fs::path dir = fs::absolute(from_file, ec).parent_path();
    const fs::path rel = fs::relative(fs::absolute(path, ec), dir, ec);
    const std::string r = rel.generic_string();
    // in the same folder tree (or one level up) the two move together; else absolute
    if (ec || rel.empty() || r.rfind("../..", 0) == 0) return fs::absolute(path, ec).string();
    return r;
}

EnvironmentSpec parse_environment(std::string_view text, const std::string& file) {
    const xml::Document doc(text, file, "environment");
    return read_environment_element(doc.root());
}

EnvironmentSpec read_environment(const std::string& path) {
    return parse_environment(xml::read_text(path), path);
}

std::string format_environment(const EnvironmentSpec& env, const std::string& file) {
    WorldSpec world = env.world;
    world.robots.clear();
    validate(world);
    xml::Writer w;
    w.open("environment");
    w.attr("gravity", world.gravity);
    w.open("floor");
    if (!world.floor.enabled) w.attr("enabled", false);
    w.attr("friction", world.floor.friction);
    // the floor's contact as it runs, defaults written out: the file keeps its physics if a
    // later version changes a default
    if (world.floor.rigid) {
        w.attr("rigid", true);
    } else {
        w.attr("stiffness", world.floor.stiffness.value_or(kDefaultFloorStiffness));
        w.attr("damping", world.floor.damping.value_or(kDefaultFloorDamping));
    }
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
    write_objects(w, "wall", world.walls);
    write_objects(w, "ramp", world.ramps);
    write_objects(w, "stairs", world.stairs);
    write_objects(w, "cylinder", world.cylinders);
    write_objects(w, "pipe", world.pipes);
    write_objects(w, "rubble", world.rubble);
    write_heightfields(w, world.heightfields, file);
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
    write_file_atomic(path, checked_environment_text(format_environment(env, path)),
                      MissingFolders::create);
}

std::string checked_environment_text(std::string text) {
    // a file gaitlab would refuse to read back is not written: heights written out as numbers
    // (a generated terrain, or a grid of millions) can pass the reader's limit
    if (text.size() > kMaxInputBytes) {
        throw SpecError(fmt::format(
            "the environment would be a file of {:.0f} MiB, more than the {} gaitlab reads: "
            "make its heightfields smaller or coarser (fewer samples), or keep the terrain as an "
            "image",
            std::ceil(static_cast<double>(text.size()) / (1 << 20)),
            describe_size(kMaxInputBytes)));
    }
    return text;
}

}  // namespace gaitlab
