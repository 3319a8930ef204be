#include "make.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gaitlab/suggest.h"
#include "gaitlab/terminal.h"
#include "gaitlab/xml.h"
#include "parts.h"
#include "shell_word.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

int whole_number(const char* option, const std::string& text) {
    int v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size()) {
        throw Error(fmt::format("{}: a whole number expected (got '{}')", option, text));
    }
    return v;
}

double number(const char* option, const std::string& text) {
    double v = 0;
    if (!parse_number(text, v)) {
        throw Error(fmt::format("{}: a number expected (got '{}')", option, text));
    }
    return v;
}

// the folder a file goes into exists after this (or IoError)
void make_parent(const std::string& path) {
    const fs::path parent = fs::absolute(path).parent_path();
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec) throw IoError(fmt::format("{}: cannot create the folder: {}", path, ec.message()));
}

// a file that must exist before make reads it
void need_file(const char* option, const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        throw Error(fmt::format("{} {}: {}", option, path,
                                fs::exists(path, ec) ? "not a regular file" : "no such file"));
    }
}

// `-o path` may replace a file only of the kind it writes (`kind`: robot, actuation,
// environment, simulation), as when a part is made again; any other file would be lost, so it is
// refused unless `force`; never one of the files read (`inputs`: option, path)
void check_output(const std::string& path, const std::string& kind, bool force,
                  const std::vector<std::pair<const char*, std::string>>& inputs) {
    if (path.empty()) throw Error("-o: a file name expected");
    std::error_code ec;
    for (const auto& [option, input] : inputs) {
        if (!input.empty() && fs::equivalent(path, input, ec)) {
            throw Error(
                fmt::format("-o {} is the {} file, which would be lost: write to another "
                            "file",
                            path, option));
        }
    }
    if (force || !fs::exists(path, ec) || !fs::is_regular_file(path, ec)) return;
    try {
        if (kind == "robot") {
            read_robot(path);
        } else if (kind == "actuation") {
            read_actuation(path);
        } else if (kind == "environment") {
            read_environment(path);
        } else {
            read_simulation(path);
        }
    } catch (const std::exception&) {
        throw Error(
            fmt::format("-o {} exists and is not {} {} file, so it would be lost: write "
                        "to another file, or add --force to replace it",
                        path, kind[0] == 'a' || kind[0] == 'e' ? "an" : "a", kind));
    }
}

}  // namespace

struct MakeCommand::Args {
    CLI::App* make = nullptr;
    CLI::App *robot = nullptr, *actuation = nullptr, *world = nullptr, *sim = nullptr;
    std::string out;
    // robot
    std::string name = "robot", modules = "8", connection = "pitch-pitch", module = "y1";
    std::vector<std::string> sensors;
    // actuation, sim, world
    std::string robot_file;
    std::vector<std::string> groups;
    // world
    std::string preset = "flat", friction, place;
    std::vector<std::string> params;
    // sim
    std::string actuation_file, world_file, sim_name, duration = "10", dt = "0.001",
                                                      control_every = "30";
    bool no_record = false;
    bool force = false;
};

MakeCommand::MakeCommand(CLI::App& app) : a_(std::make_unique<Args>()) {
    Args& a = *a_;
    a.make = app.add_subcommand(
        "make", "Make one part of a simulation as a file: robot, world, actuation or sim");
    a.make->allow_extras();
    a.make->require_subcommand(0, 1);
    a.make->footer(
        "Each part is its own file, so one robot serves several actuations and worlds:\n"
        "  gaitlab make robot --modules 8 --connection pitch-yaw -o snake.xml\n"
        "  gaitlab make actuation --robot snake.xml --group pitch=sine:amplitude=40 "
        "--group yaw=offset -o act.xml\n"
        "  gaitlab make world --preset ramp --friction 0.8 -o ramp.xml\n"
        "  gaitlab make sim --robot snake.xml --actuation act.xml --world ramp.xml "
        "--duration 20 -o sim.xml\n"
        "  gaitlab run sim.xml\n"
        "See docs/console.md.");
    const auto output = [&](CLI::App* sub) {
        sub->allow_extras();
        sub->add_option("-o,--output", a.out, "The file to write (its folder is created)")
            ->required()
            ->type_name("FILE");
        sub->add_flag("--force", a.force,
                      "Replace FILE even if it is not a file of this kind (a file of this kind "
                      "is always replaced)");
    };

    a.robot = a.make->add_subcommand("robot", "A robot file: a chain of modules with sensors");
    output(a.robot);
    a.robot->add_option("--name", a.name, "The robot's name")
        ->type_name("NAME")
        ->capture_default_str();
    a.robot->add_option("--modules", a.modules, "Number of modules, 1 to 1000")
        ->type_name("N")
        ->capture_default_str();
    a.robot->add_option("--connection", a.connection, "pitch-pitch, pitch-yaw or yaw-yaw")
        ->type_name("C")
        ->capture_default_str();
    a.robot->add_option("--module", a.module, "Module type: y1 or cube (docs/modules.md)")
        ->type_name("M")
        ->capture_default_str();
    a.robot
        ->add_option("--sensor", a.sensors,
                     "A sensor, KIND or KIND:N (joint, imu, contact, range, position; N the "
                     "module, or the joint); repeat for more")
        ->type_name("KIND[:N]");

    a.actuation = a.make->add_subcommand(
        "actuation", "An actuation file: which controller drives which joints of a robot");
    output(a.actuation);
    a.actuation->add_option("--robot", a.robot_file, "The robot file it drives")
        ->required()
        ->type_name("FILE");
    a.actuation
        ->add_option("--group", a.groups,
                     "JOINTS=CONTROLLER[:PARAM=VALUE...]: JOINTS pitch, yaw, all or numbers "
                     "(1,3,5); CONTROLLER a built-in (sine, offset, hopf, ...), template/NAME or "
                     "FILE.lua; repeat for more groups")
        ->required()
        ->type_name("SPEC");

    a.world = a.make->add_subcommand("world", "An environment file from the world library");
    output(a.world);
    a.world
        ->add_option("--preset", a.preset,
                     "flat, slippery, sticky, ramp, stairs, pipe, rubble, hills "
                     "(docs/worlds.md)")
        ->type_name("NAME")
        ->capture_default_str();
    a.world->add_option("--friction", a.friction, "Friction of the floor and objects, 0 to 1")
        ->type_name("F");
    a.world->add_option("--param", a.params, "Another parameter of the preset (slope=15)")
        ->type_name("NAME=VALUE");
    auto* place_robot = a.world->add_option("--robot", a.robot_file,
                                            "The robot file whose robot goes to the world's start");
    place_robot->type_name("FILE");
    a.world->add_option("--place", a.place, "The name of the robot that goes to the start")
        ->type_name("NAME")
        ->excludes(place_robot);

    a.sim = a.make->add_subcommand("sim", "A simulation file naming a robot, actuation and world");
    output(a.sim);
    a.sim->add_option("--robot", a.robot_file, "The robot file")->required()->type_name("FILE");
    a.sim
        ->add_option("--actuation", a.actuation_file,
                     "The actuation file (none: the robot "
                     "lies still)")
        ->type_name("FILE");
    a.sim->add_option("--world", a.world_file, "The environment file")
        ->required()
        ->type_name("FILE");
    a.sim->add_option("--name", a.sim_name, "The simulation's name (default: FILE's name)")
        ->type_name("NAME");
    a.sim
        ->add_option("--duration", a.duration,
                     "Simulated time `gaitlab run` runs, s (0 to 2^53 ticks of --dt)")
        ->type_name("S")
        ->capture_default_str();
    a.sim->add_option("--dt", a.dt, "Physics step, s")->type_name("S")->capture_default_str();
    a.sim->add_option("--control-every", a.control_every, "Physics steps between controller steps")
        ->type_name("N")
        ->capture_default_str();
    a.sim->add_flag("--no-record", a.no_record, "`gaitlab run` records nothing of it");
}

MakeCommand::~MakeCommand() = default;

bool MakeCommand::chosen() const {
    return a_->make->parsed();
}

int MakeCommand::run() {
    Args& a = *a_;
    CLI::App* sub = nullptr;
    for (CLI::App* s : {a.robot, a.actuation, a.world, a.sim})
        if (s->parsed()) sub = s;
    if (!sub) {
        print_message(stderr,
                      "gaitlab: say what to make: gaitlab make robot|world|actuation|sim ... -o "
                      "FILE (see 'gaitlab make --help')\n");
        return 2;
    }
    const std::string command = "gaitlab make " + sub->get_name();
    // unknown options, with the closest option of the command
    for (const std::string& arg : sub->remaining()) {
        std::vector<std::string> options{"--help"};
        for (const CLI::Option* o : sub->get_options())
            for (const std::string& l : o->get_lnames())
                options.push_back("--" + l);
        const std::string name = arg.substr(0, arg.find('='));
        if (arg.size() > 1 && arg[0] == '-') {
            print_message(stderr, "gaitlab: unknown option '%s' for '%s'%s (see '%s --help')\n",
                          name.c_str(), command.c_str(), did_you_mean(name, options).c_str(),
                          command.c_str());
        } else {
            print_message(stderr, "gaitlab: unexpected argument '%s' for '%s' (see '%s --help')\n",
                          arg.c_str(), command.c_str(), command.c_str());
        }
        return 2;
    }
    try {
        const std::string kind = sub == a.robot       ? "robot"
                                 : sub == a.actuation ? "actuation"
                                 : sub == a.world     ? "environment"
                                                      : "simulation";
        check_output(a.out, kind, a.force,
                     {{"--robot", a.robot_file},
                      {"--actuation", a.actuation_file},
                      {"--world", a.world_file}});
        PartMaker maker;
        make_parent(a.out);
        if (sub == a.robot) {
            RobotChoice r;
            r.name = a.name;
            r.modules = whole_number("--modules", a.modules);
            r.connection = a.connection;
            r.module = a.module;
            for (const std::string& s : a.sensors)
                r.sensors.push_back(parse_sensor(s));
            maker.write_robot(r, a.out);
            print_message(stdout, "wrote %s (robot '%s': %d modules, %s)\n", a.out.c_str(),
                          r.name.c_str(), r.modules, r.connection.c_str());
        } else if (sub == a.actuation) {
            need_file("--robot", a.robot_file);
            std::vector<GroupChoice> groups;
            for (const std::string& g : a.groups)
                groups.push_back(parse_group(g));
            maker.write_actuation(a.robot_file, groups, a.out);
            print_message(stdout, "wrote %s (%zu %s)\n", a.out.c_str(), groups.size(),
                          groups.size() == 1 ? "group" : "groups");
        } else if (sub == a.world) {
            WorldChoice w;
            w.preset = a.preset;
            // all the --param options at once: a name given twice is refused
            std::string params;
            for (const std::string& p : a.params)
                params += p + " ";
            w.params = parse_params(params);
            if (!a.friction.empty()) {
                for (const auto& [name, value] : w.params) {
                    if (name == "friction")
                        throw Error(
                            "friction is given twice (--friction and --param "
                            "friction=...): give it once");
                }
                w.params.emplace_back("friction", number("--friction", a.friction));
            }
            if (!a.robot_file.empty()) {
                need_file("--robot", a.robot_file);
                w.place = maker.robot_name(a.robot_file);
            } else {
                w.place = a.place;
            }
            maker.write_world(w, a.out);
            print_message(stdout, "wrote %s (world '%s')\n", a.out.c_str(), w.preset.c_str());
        } else {
            need_file("--robot", a.robot_file);
            if (!a.actuation_file.empty()) need_file("--actuation", a.actuation_file);
            need_file("--world", a.world_file);
            SimChoice s;
            s.name = a.sim_name.empty() ? fs::path(a.out).stem().string() : a.sim_name;
            s.duration = number("--duration", a.duration);
            s.dt = number("--dt", a.dt);
            s.control_every = whole_number("--control-every", a.control_every);
            s.record = !a.no_record;
            maker.write_sim(s, a.robot_file, a.actuation_file, a.world_file, a.out);
            print_message(stdout, "wrote %s (run it: gaitlab run %s)\n", a.out.c_str(),
                          shell_word(a.out).c_str());
        }
    } catch (const std::exception& e) {
        // "gaitlab: make robot: ..."
        print_message(stderr, "gaitlab: %s: %s\n", command.c_str() + 8, e.what());
        return 1;
    }
    return 0;
}

}  // namespace gaitlab::cli
