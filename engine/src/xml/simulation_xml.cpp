// Simulation (master) files: the options of a run and the files of its parts, with paths
// relative to the master's folder. See docs/formats.md.
#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/checked.h"
#include "gaitlab/files.h"
#include "gaitlab/robot.h"
#include "gaitlab/xml.h"
#include "xml/xml_io.h"

namespace gaitlab {

namespace {

using xml::Element;

// a referenced file, which must be one gaitlab can read (a missing file, a directory, a
// device or a huge file is named with its resolved path and the reason)
std::string read_ref(const Element& e, const char* attr, bool required) {
    if (!required && !e.has(attr)) return "";
    const std::string path = e.required_string(attr);
    if (path.empty()) e.fail(fmt::format("attribute '{}' is empty", attr));
    try {
        check_file(resolve_path(e.file(), path));
    } catch (const ReadError& err) {
        e.fail(fmt::format("attribute '{}': {}", attr, err.what()));
    }
    return path;
}

ControllerErrorPolicy parse_policy(const Element& e) {
    const std::string p = e.string("on_controller_error", "stop");
    for (ControllerErrorPolicy c : {ControllerErrorPolicy::stop, ControllerErrorPolicy::continue_,
                                    ControllerErrorPolicy::pause}) {
        if (p == to_string(c)) return c;
    }
    e.fail(fmt::format(
        "attribute 'on_controller_error': 'stop', 'continue' or 'pause' expected, got '{}'", p));
}

SimulationFile read_simulation_element(const Element& root) {
    root.allow(xml::attrs::simulation);
    SimulationFile s;
    s.line = root.line();
    s.name = root.string("name", s.name);
    root.check([&] { validate_name("simulation name", s.name); });
    s.duration = root.number("duration", s.duration);
    SimulationOptions& o = s.options;
    o.dt = root.number("dt", o.dt);
    const long long ce = root.integer("control_every", o.control_every);
    const long long it = root.integer("solver_iterations", o.solver_iterations);
    const long long newton = root.integer("newton_steps", o.newton_steps);
    root.check([&] {
        o.control_every = checked_int("control_every", ce, 1, kMaxControlEvery);
        o.solver_iterations = checked_int("solver_iterations", it, 1, kMaxSolverIterations);
        // not given: the simulation chooses for its world (automatic_newton_steps)
        if (root.has("newton_steps"))
            o.newton_steps = checked_int("newton_steps", newton, 0, kMaxNewtonSteps);
    });
    const long long seed = root.integer("seed", 0);
    if (seed < 0) root.fail(fmt::format("seed must be >= 0 (got {})", seed));
    o.seed = static_cast<std::uint64_t>(seed);
    o.on_controller_error = parse_policy(root);
    const std::string solver = root.string("solver", to_string(o.solver));
    if (!parse_solver(solver, o.solver)) {
        root.fail(fmt::format("attribute 'solver': {} expected, got '{}'", solver_names(), solver));
    }
    root.check([&] {
        validate(o);
        // `gaitlab run` runs it for round(duration / dt) ticks: they must fit
        checked_ticks("duration", s.duration, o.dt);
    });
    bool env = false, record = false;
    for (const Element& k : root.children({"environment", "robot", "record"})) {
        const std::string kind = k.name();
        k.children({});
        if (kind == "environment") {
            if (env) k.fail("one <environment> per simulation expected");
            env = true;
            k.allow(xml::attrs::simulation_environment);
            s.environment = read_ref(k, "file", true);
        } else if (kind == "robot") {
            k.allow(xml::attrs::simulation_robot);
            RobotEntry r;
            r.line = k.line();
            r.robot = read_ref(k, "file", true);
            r.actuation = read_ref(k, "actuation", false);
            s.robots.push_back(r);
        } else {
            if (record) k.fail("one <record> per simulation expected");
            record = true;
            k.allow(xml::attrs::record);
            if (k.has("enabled")) s.record.enabled = k.boolean("enabled", true);
            s.record.dir = k.string("dir", "");
            const long long every = k.integer("every", 0);
            k.check([&] { s.record.every = checked_int("every", every, 0, kMaxControlEvery); });
            s.record.flush_seconds = k.number("flush_seconds", s.record.flush_seconds);
            if (!(s.record.flush_seconds > 0)) {
                k.fail(fmt::format("flush_seconds must be > 0 s (got {})", s.record.flush_seconds));
            }
        }
    }
    if (!env) root.fail("an <environment file=\"...\"/> element is required");
    return s;
}

}  // namespace

SimulationFile parse_simulation(std::string_view text, const std::string& file) {
    const xml::Document doc(text, file, "simulation");
    return read_simulation_element(doc.root());
}

SimulationFile read_simulation(const std::string& path) {
    return parse_simulation(xml::read_text(path), path);
}

std::string format_simulation(const SimulationFile& s) {
    validate(s.options);
    if (s.environment.empty()) throw SpecError("a simulation file needs an environment file");
    xml::Writer w;
    w.open("simulation");
    w.attr("name", s.name);
    w.attr("duration", s.duration);
    const SimulationOptions& o = s.options;
    w.attr("dt", o.dt);
    w.attr_int("control_every", o.control_every);
    w.attr_int("solver_iterations", o.solver_iterations);
    w.attr_int("seed", static_cast<long long>(o.seed));
    w.attr("on_controller_error", to_string(o.on_controller_error));
    w.attr("solver", to_string(o.solver));
    // only when given: not given, the simulation chooses for its world (and every file written
    // before it existed round-trips unchanged)
    if (o.newton_steps != kAutomaticNewtonSteps) w.attr_int("newton_steps", o.newton_steps);
    w.open("environment");
    w.attr("file", s.environment);
    w.close();
    for (const RobotEntry& r : s.robots) {
        w.open("robot");
        w.attr("file", r.robot);
        if (!r.actuation.empty()) w.attr("actuation", r.actuation);
        w.close();
    }
    w.open("record");
    if (s.record.enabled) w.attr("enabled", *s.record.enabled);
    if (!s.record.dir.empty()) w.attr("dir", s.record.dir);
    w.attr_int("every", s.record.every);
    w.attr("flush_seconds", s.record.flush_seconds);
    w.close();
    w.close();
    return w.text();
}

void write_simulation(const std::string& path, const SimulationFile& s) {
    write_file_atomic(path, format_simulation(s), MissingFolders::create);
}

}  // namespace gaitlab
