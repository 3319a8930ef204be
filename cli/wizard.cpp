#include "wizard.h"

#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gaitlab/files.h"
#include "gaitlab/options.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/suggest.h"
#include "gaitlab/terminal.h"
#include "parts.h"
#include "shell_word.h"

namespace gaitlab::cli {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// signals

// the first SIGINT, SIGTERM or SIGHUP, 0 if none
volatile std::sig_atomic_t g_signal = 0;
// the host running the project, while it runs (a signal interrupts it)
std::atomic<scripting::LuaHost*> g_host{nullptr};

extern "C" void on_wizard_signal(int sig) {
    if (g_signal == 0) g_signal = sig;
    if (scripting::LuaHost* host = g_host.load()) host->interrupt(sig);
}

// no SA_RESTART: a read waiting for an answer fails with EINTR, and the wizard stops there
void catch_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_wizard_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        sigaction(sig, &sa, nullptr);
}

// the wizard stops: at the end of input (signal 0) or by a signal
struct Stopped {
    int signal = 0;
    std::string question;
};

void check_signal(const std::string& where) {
    if (g_signal != 0) throw Stopped{g_signal, where};
}

// ---------------------------------------------------------------------------------------------
// questions and answers

// (all of it: an answer piped in may hold a NUL byte)
void say(const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
}

// the longest answer read, bytes
constexpr size_t kMaxAnswer = 64 * 1024;
// refused piped answers to one question before the wizard stops
constexpr int kMaxRefused = 10;

// the wizard stops: an answer longer than kMaxAnswer
struct TooLong {
    std::string question;
};

// the wizard stops: kMaxRefused piped answers to one question were refused
struct Refused {
    std::string question;
    int count = 0;
};

// Reads answers, one line each, from standard input (unbuffered, so nothing is read past the
// answer); with `defaults`, answers every question with its default without asking.
class Prompter {
  public:
    explicit Prompter(bool defaults) : defaults_(defaults), tty_(::isatty(STDIN_FILENO) != 0) {}

    bool defaults() const { return defaults_; }
    bool tty() const { return tty_; }

    // asks until `accept` takes the answer (Enter: `def`); accept throws Error to explain
    // why an answer does not do, and the question is asked again
    template <typename F>
    void ask(const std::string& question, const std::string& def, F accept) {
        int refused = 0;
        for (;;) {
            std::string answer = def;
            if (!defaults_) {
                say(fmt::format("{} [{}]: ", question, def.empty() ? "none" : def));
                const std::string line = read_line(question);
                // piped answers show as if typed, with the bytes a terminal would act on (an
                // escape sequence in a file of answers) written out as \xNN
                if (!tty_) say(terminal_line(line) + "\n");
                if (!trim(line).empty()) answer = trim(line);
            }
            try {
                accept(answer);
                return;
            } catch (const Error& e) {
                if (defaults_) throw;
                say(terminal_text(fmt::format("  ! {}\n", e.what())));
                // piped answers that keep being refused (`yes | gaitlab new`) would be asked
                // for forever: a person at a terminal can always try again, a script cannot
                if (!tty_ && ++refused >= kMaxRefused) throw Refused{question, kMaxRefused};
            }
        }
    }

    static std::string trim(const std::string& s) {
        const size_t a = s.find_first_not_of(" \t\r");
        if (a == std::string::npos) return "";
        return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
    }

  private:
    std::string read_line(const std::string& question) {
        std::string line;
        for (;;) {
            check_signal(question);
            char c = 0;
            const ssize_t n = ::read(STDIN_FILENO, &c, 1);
            if (n < 0 && errno == EINTR) continue;  // a signal: check_signal stops
            if (n <= 0) {
                if (!line.empty()) return line;
                say("\n");
                throw Stopped{0, question};
            }
            if (c == '\n') return line;
            // an endless line (`gaitlab new < /dev/zero`) would fill the memory
            if (line.size() >= kMaxAnswer) throw TooLong{question};
            line += c;
        }
    }

    bool defaults_;
    bool tty_;
};

void explain(const Prompter& in, const std::string& text) {
    if (!in.defaults()) say(text);
}

bool yes_no(const std::string& answer) {
    std::string a;
    for (char c : answer)
        a += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (a == "y" || a == "yes") return true;
    if (a == "n" || a == "no") return false;
    throw Error(fmt::format("'{}': answer yes or no", answer));
}

// one of `names`, by name or by its number in the list shown
std::string choose(const std::string& answer, const std::vector<std::string>& names) {
    int n = 0;
    const auto r = std::from_chars(answer.data(), answer.data() + answer.size(), n);
    if (r.ec == std::errc() && r.ptr == answer.data() + answer.size()) {
        if (n >= 1 && n <= static_cast<int>(names.size())) return names[static_cast<size_t>(n - 1)];
        throw Error(
            fmt::format("'{}': choose a number from 1 to {}, or a name", answer, names.size()));
    }
    if (std::find(names.begin(), names.end(), answer) != names.end()) return answer;
    throw Error(fmt::format("'{}' is not one of the choices{} ({})", answer,
                            did_you_mean(answer, names), fmt::join(names, ", ")));
}

int whole_number(const std::string& answer, int min, int max) {
    int n = 0;
    const auto r = std::from_chars(answer.data(), answer.data() + answer.size(), n);
    if (r.ec != std::errc() || r.ptr != answer.data() + answer.size() || n < min || n > max) {
        throw Error(fmt::format("'{}': a whole number from {} to {} expected", answer, min, max));
    }
    return n;
}

double number(const std::string& answer) {
    double v = 0;
    if (!parse_number(answer, v)) throw Error(fmt::format("'{}': a number expected", answer));
    return v;
}

// a robot name as part of a folder name: letters, digits, '-' and '_' kept, the rest '_'
std::string folder_name(const std::string& name) {
    std::string out;
    for (char c : name) {
        const auto u = static_cast<unsigned char>(c);
        out += std::isalnum(u) || c == '-' || c == '_' ? c : '_';
    }
    if (out.empty() || out[0] == '-' || out[0] == '.') out = "robot" + out;
    return out.substr(0, 64);
}

bool empty_folder(const fs::path& dir) {
    std::error_code ec;
    return fs::is_directory(dir, ec) && fs::is_empty(dir, ec);
}

// one-line pictures of what each built-in controller does
const std::map<std::string, std::string>& builtin_lines() {
    static const std::map<std::string, std::string> lines{
        {"sine", "a sine wave along the body, each joint a bit later than the last"},
        {"offset", "holds every joint at one angle (bends or turns the robot)"},
        {"phase_chain", "a chain of phase oscillators that settle into a travelling wave"},
        {"hopf", "coupled Hopf oscillators: a smooth rhythm that recovers when disturbed"},
        {"matsuoka", "half-centre neurons inhibiting each other, as in M-TRAN robots"},
        {"hindmarsh_rose", "bursting model neurons: rhythmic bursts of movement"},
        {"distributed", "one oscillator per module, each coupled to its neighbours only"},
    };
    return lines;
}

const std::map<std::string, std::string>& template_lines() {
    static const std::map<std::string, std::string> lines{
        {"sine", "the sine wave, as Lua you can read and change"},
        {"cpg_chain", "a central pattern generator: oscillators pulling on their neighbours"},
        {"blank", "the smallest controller, holds its joints: a start for your own"},
    };
    return lines;
}

// ---------------------------------------------------------------------------------------------
// the project

// a controller the wizard writes into the project's controllers/ folder
struct ProjectController {
    bool is_new = false;  // a new controller (else a copied template)
    std::string name;     // template name, or the new controller's
    std::string base;     // the file's name without .lua (a template's copy gives way to a
                          // new controller of the same name: sine_2.lua)
    NewController def;    // the new one's declaration
    std::string file() const { return "controllers/" + base + ".lua"; }
};

struct Project {
    RobotChoice robot;
    std::vector<GroupChoice> groups;         // controllers of kind file are project files
    std::vector<ProjectController> written;  // controller files to write
    WorldChoice world;
    SimChoice sim;
};

class Wizard {
  public:
    Wizard(Prompter& in, PartMaker& maker) : in_(in), maker_(maker) {}

    Project ask() {
        explain(in_,
                "gaitlab new: build a modular robot, make it move, and simulate it.\n"
                "Each question has an answer in [brackets]: press Enter to take it. Ctrl-C or "
                "Ctrl-D stops\nwithout writing anything.\n\n");
        ask_robot();
        ask_controllers();
        ask_world();
        ask_sim();
        return p_;
    }

  private:
    void ask_robot() {
        RobotChoice& r = p_.robot;
        explain(in_, "A modular robot is a chain of identical motor modules joined end to end.\n");
        in_.ask("Robot name", "snake", [&](const std::string& a) {
            RobotChoice t = r;
            t.name = a;
            maker_.check_robot(t);
            r = t;
        });
        explain(in_,
                "\nEach module is a small box with a servo motor that turns the joint between "
                "it and the\nnext one; more modules make a longer robot.\n");
        in_.ask("Number of modules", "8", [&](const std::string& a) {
            RobotChoice t = r;
            t.modules = whole_number(a, 1, 1000);
            maker_.check_robot(t);
            r = t;
        });
        const std::vector<std::string> connections{"pitch-pitch", "pitch-yaw", "yaw-yaw"};
        explain(in_,
                "\nHow the joints are turned decides how the robot moves:\n"
                "  1) pitch-pitch  every joint bends up and down: it moves like a caterpillar\n"
                "  2) pitch-yaw    joints alternate up-down and left-right: it can also turn "
                "and roll\n"
                "  3) yaw-yaw      every joint bends left and right: it crawls like a snake on "
                "the floor\n");
        in_.ask("Connection", "pitch-pitch", [&](const std::string& a) {
            RobotChoice t = r;
            t.connection = choose(a, connections);
            maker_.check_robot(t);
            r = t;
        });
        explain(in_,
                "\nSensors measure what the robot feels; a recorded run keeps their readings.\n"
                "  joint     angle, speed and torque of every joint\n"
                "  imu       tilt and turning speed of the head module\n"
                "  contact   whether each module touches something\n"
                "  range     distance to the nearest obstacle ahead of the head\n"
                "  position  where the robot is and how fast it goes\n"
                "Name any, separated by spaces; KIND:N puts one on module N only (imu:3).\n");
        in_.ask("Sensors", "", [&](const std::string& a) {
            RobotChoice t = r;
            t.sensors.clear();
            std::string word;
            const std::string list = a == "none" ? "" : a + " ";
            for (char c : list) {
                if (c == ' ' || c == ',') {
                    if (!word.empty()) t.sensors.push_back(parse_sensor(word));
                    word.clear();
                } else {
                    word += c;
                }
            }
            maker_.check_robot(t);
            r = t;
        });
    }

    // the joints a controller drives unless told: the robot's natural group, or none (an
    // answer needed) when an earlier controller drives that group already (one controller per
    // group)
    std::string default_joints(size_t k) const {
        const std::string& c = p_.robot.connection;
        const std::string joints = c == "yaw-yaw"     ? "yaw"
                                   : c != "pitch-yaw" ? "all"
                                   : k == 0           ? "pitch"
                                   : k == 1           ? "yaw"
                                                      : "all";
        for (const GroupChoice& g : p_.groups)
            if (g.joints == joints) return "";
        return joints;
    }

    void ask_controllers() {
        explain(in_,
                "\nA controller makes joints move: many times a second it says which angle each "
                "joint\nshould turn to. Each controller drives a group of joints.\n");
        for (size_t k = 0;; ++k) {
            GroupChoice g;
            ask_controller(g.controller, k);
            explain(in_,
                    "\nWhich joints does it drive? pitch (the joints bending up and down), yaw "
                    "(left and\nright), all, or joint numbers from the tail like 1 3 5.\n");
            in_.ask("Joints", default_joints(k), [&](const std::string& a) {
                std::string error;
                const std::string joints = parse_joints(a, error);
                if (joints.empty()) throw Error(error);
                std::vector<GroupChoice> groups = p_.groups;
                g.joints = joints;
                groups.push_back(g);
                maker_.check_groups(p_.robot, project_groups(groups));
            });
            p_.groups.push_back(g);
            bool more = false;
            explain(in_,
                    "\nAnother controller can drive other joints (where groups only partly "
                    "overlap, their angles add up;\nthe same group twice is refused).\n");
            in_.ask("Another controller", "no", [&](const std::string& a) { more = yes_no(a); });
            if (!more) break;
        }
    }

    // the groups as they can be checked before any file is written: a copied template as the
    // template itself, a new controller (its declaration is checked on its own) as a controller
    // of its name that does nothing, so messages name it
    std::vector<GroupChoice> project_groups(std::vector<GroupChoice> groups) const {
        for (GroupChoice& g : groups) {
            if (g.controller.kind != ControllerChoice::Kind::file) continue;
            if (const auto t = c_template_.find(g.controller.name); t != c_template_.end()) {
                g.controller.kind = ControllerChoice::Kind::template_;
                g.controller.name = t->second;
            } else {
                g.controller = ControllerChoice{
                    ControllerChoice::Kind::stub, fs::path(g.controller.name).stem().string(), {}};
            }
        }
        return groups;
    }

    void ask_controller(ControllerChoice& c, size_t k) {
        explain(in_, fmt::format("\nController {}:\n"
                                 "  1) built-in   a controller that comes with gaitlab\n"
                                 "  2) template   a Lua controller copied into your project, to "
                                 "read and change\n"
                                 "  3) new        you name its parameters; gaitlab writes the "
                                 "Lua file for you to fill in\n",
                                 k + 1));
        std::string kind;
        in_.ask("Kind of controller", "built-in", [&](const std::string& a) {
            kind = choose(a, {"built-in", "template", "new"});
        });
        if (kind == "new") {
            ask_new_controller(c);
            return;
        }
        const bool builtin = kind == "built-in";
        const std::vector<std::string> names = builtin ? maker_.builtins() : maker_.templates();
        const auto& lines = builtin ? builtin_lines() : template_lines();
        std::string list;
        for (size_t i = 0; i < names.size(); ++i) {
            const auto line = lines.find(names[i]);
            list += fmt::format("  {}) {:<15} {}\n", i + 1, names[i],
                                line == lines.end() ? "" : line->second);
        }
        explain(in_, (builtin ? "\nBuilt-in controllers (docs/controllers.md):\n"
                              : "\nTemplates (docs/lua-controllers.md):\n") +
                         list);
        std::string name;
        in_.ask(builtin ? "Built-in controller" : "Template", "sine",
                [&](const std::string& a) { name = choose(a, names); });
        c.kind = builtin ? ControllerChoice::Kind::builtin : ControllerChoice::Kind::template_;
        c.name = name;
        std::string table;
        for (const ParamInfo& p : maker_.controller_params(c)) {
            table +=
                fmt::format("  {:<16} {:>8} {:<5} from {} to {}\n", p.name, number_text(p.value),
                            p.unit, number_text(p.min), number_text(p.max));
        }
        explain(in_,
                "\nIts parameters start at these values; change any with NAME=VALUE "
                "(amplitude=30 phase=-120).\n" +
                    table);
        in_.ask("Parameter changes", "", [&](const std::string& a) {
            ControllerChoice t = c;
            t.params = a == "none" ? ParamValues{} : parse_params(a);
            maker_.check_controller(t);
            c = t;
        });
        if (!builtin) {
            // the template is copied into the project, and the group uses that copy
            const auto copied = std::find_if(
                p_.written.begin(), p_.written.end(),
                [&](const ProjectController& w) { return !w.is_new && w.name == name; });
            ProjectController w;
            if (copied != p_.written.end()) {
                w = *copied;
            } else {
                w.name = name;
                w.base = name;
                for (int n = 2; file_taken(w.base); ++n)
                    w.base = fmt::format("{}_{}", name, n);
                p_.written.push_back(w);
            }
            c.kind = ControllerChoice::Kind::file;
            c.name = w.file();
            c_template_[c.name] = name;
        }
    }

    // whether controllers/BASE.lua is already one of the project's files
    bool file_taken(const std::string& base) const {
        return std::any_of(p_.written.begin(), p_.written.end(),
                           [&](const ProjectController& w) { return w.base == base; });
    }

    void ask_new_controller(ControllerChoice& c) {
        NewController def;
        def.params.clear();
        explain(in_, "\nYour controller is a Lua file; its name names the file.\n");
        in_.ask("Controller name", "my_controller", [&](const std::string& a) {
            NewController t = def;
            t.name = a;
            maker_.check_new_controller(t);
            if (file_taken(a)) {
                throw Error(
                    fmt::format("'{}' is already a controller of this project: choose "
                                "another name",
                                a));
            }
            def = t;
        });
        explain(in_,
                "\nParameters are the numbers you tune, even while it runs (an amplitude, "
                "a frequency).\n");
        int count = 0;
        in_.ask("How many parameters", "2",
                [&](const std::string& a) { count = whole_number(a, 0, 20); });
        static const NewParam kSuggested[] = {{"amplitude", 40, 0, 90, "deg"},
                                              {"frequency", 0.5, 0, 5, "Hz"},
                                              {"phase", 120, -180, 180, "deg"}};
        for (int i = 0; i < count; ++i) {
            NewParam p =
                i < 3 ? kSuggested[i] : NewParam{fmt::format("param{}", i + 1), 0, -100, 100, ""};
            const std::string n = std::to_string(i + 1);
            in_.ask("Parameter " + n + ": name", p.name, [&](const std::string& a) {
                NewController t = def;
                NewParam q = p;
                q.name = a;
                q.value = 0;
                q.min = -1;
                q.max = 1;
                t.params.push_back(q);
                maker_.check_new_controller(t);
                p.name = a;
            });
            in_.ask("  initial value of " + p.name, number_text(p.value),
                    [&](const std::string& a) { p.value = number(a); });
            const std::string range =
                number_text(std::min(p.min, p.value)) + " " + number_text(std::max(p.max, p.value));
            in_.ask("  range of " + p.name + ", as MIN MAX", range, [&](const std::string& a) {
                std::vector<std::string> words;
                std::string word;
                for (char ch : a + " ") {
                    if (ch == ' ' || ch == '\t' || ch == ',') {
                        if (!word.empty()) words.push_back(word);
                        word.clear();
                    } else {
                        word += ch;
                    }
                }
                if (words.size() != 2) {
                    throw Error(words.size() < 2 ? std::string("two numbers expected: MIN MAX")
                                                 : fmt::format("'{}': two numbers expected: "
                                                               "MIN MAX",
                                                               a));
                }
                NewParam q = p;
                q.min = number(words[0]);
                q.max = number(words[1]);
                NewController t = def;
                t.params.push_back(q);
                maker_.check_new_controller(t);
                p = q;
            });
            in_.ask("  unit of " + p.name + " (deg, Hz, s, ...)", p.unit,
                    [&](const std::string& a) {
                        NewController t = def;
                        NewParam q = p;
                        q.unit = a == "none" ? "" : a;
                        t.params.push_back(q);
                        maker_.check_new_controller(t);
                        p = q;
                    });
            def.params.push_back(p);
        }
        explain(in_,
                "\nPer-joint values are numbers it keeps for each joint (a clock, the "
                "angle sent):\nthey are recorded and can be plotted.\n");
        in_.ask("Per-joint values", "time angle", [&](const std::string& a) {
            NewController t = def;
            t.values.clear();
            std::string word;
            for (char ch : (a == "none" ? std::string() : a) + " ") {
                if (ch == ' ' || ch == ',') {
                    if (!word.empty()) t.values.push_back(word);
                    word.clear();
                } else {
                    word += ch;
                }
            }
            maker_.check_new_controller(t);
            def = t;
        });
        ProjectController w;
        w.is_new = true;
        w.name = def.name;
        w.base = def.name;
        w.def = def;
        p_.written.push_back(w);
        c.kind = ControllerChoice::Kind::file;
        c.name = w.file();
        c.params.clear();
        new_[c.name] = def;
    }

    // a preset's description up to its first ';' or ", " (what it is, not where the robot
    // starts or the formula of its shape): one line of a menu
    static std::string summary(const std::string& description) {
        size_t end = std::min(description.find(';'), description.find(", "));
        return description.substr(0, end);
    }

    void ask_world() {
        const std::vector<PresetInfo> presets = maker_.presets();
        std::vector<std::string> names;
        std::string list;
        for (size_t i = 0; i < presets.size(); ++i) {
            names.push_back(presets[i].name);
            list += fmt::format("  {}) {:<9} {}\n", i + 1, presets[i].name,
                                summary(presets[i].description));
        }
        explain(in_, "\nThe world is the ground and what lies on it (docs/worlds.md):\n" + list);
        WorldChoice& w = p_.world;
        in_.ask("World", "flat", [&](const std::string& a) { w.preset = choose(a, names); });
        w.place = p_.robot.name;
        const PresetInfo& preset = presets[static_cast<size_t>(
            std::find(names.begin(), names.end(), w.preset) - names.begin())];
        for (const ParamInfo& p : preset.params) {
            if (p.name != "friction") continue;
            explain(in_, "\nFriction says how much the ground grips: 0 is ice, 1 is rubber.\n");
            in_.ask("Friction", number_text(p.value), [&](const std::string& a) {
                WorldChoice t = w;
                t.params = {{"friction", number(a)}};
                maker_.check_world(t);
                w = t;
            });
        }
    }

    void ask_sim() {
        SimChoice& s = p_.sim;
        s.name = p_.robot.name;
        explain(in_, "\nThe simulation computes the physics in small time steps.\n");
        // the one robot shape whose accuracy needs more than the defaults' iterations: told
        // what the simulation does for it (automatic_newton_steps)
        if (p_.robot.connection == "pitch-yaw" && p_.robot.modules > kLongChainJoints) {
            explain(in_,
                    fmt::format("A pitch-yaw chain of more than {} modules gets {} Newton "
                                "steps in every physics step, which keep\nits gaits "
                                "accurate at a step of {:g} s or less (they take about "
                                "three times the computing time).\n",
                                kLongChainJoints, kLongChainNewtonSteps, kLongChainNewtonMaxDt));
        }
        in_.ask("Seconds to simulate", "10", [&](const std::string& a) {
            SimChoice t = s;
            t.duration = number(a);
            PartMaker::check_sim(t);
            s = t;
        });
        in_.ask("Time step, s (smaller: more accurate, slower)", number_text(s.dt),
                [&](const std::string& a) {
                    SimChoice t = s;
                    t.dt = number(a);
                    PartMaker::check_sim(t);
                    s = t;
                });
        in_.ask("Physics steps between two controller steps", std::to_string(s.control_every),
                [&](const std::string& a) {
                    SimChoice t = s;
                    t.control_every = whole_number(a, 1, 1000000);
                    PartMaker::check_sim(t);
                    s = t;
                });
        explain(in_,
                "\nA recorded run keeps joint angles, positions, sensor readings... in a "
                "folder you can plot.\n");
        in_.ask("Record the run", "yes", [&](const std::string& a) { s.record = yes_no(a); });
    }

  public:
    // what the questions decided about controller files, for writing them
    const std::map<std::string, NewController>& new_controllers() const { return new_; }
    const std::map<std::string, std::string>& copied_templates() const { return c_template_; }

  private:
    Prompter& in_;
    PartMaker& maker_;
    Project p_;
    std::map<std::string, NewController> new_;       // by project file
    std::map<std::string, std::string> c_template_;  // project file -> template
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// the command

struct NewCommand::Args {
    CLI::App* app = nullptr;
    std::string dir;
    bool defaults = false;
};

NewCommand::NewCommand(CLI::App& app) : a_(std::make_unique<Args>()) {
    a_->app = app.add_subcommand(
        "new", "Build a robot, its controllers, a world and a simulation by answering questions");
    a_->app->allow_extras();
    a_->app
        ->add_option("dir", a_->dir,
                     "The project folder to create (default: ./NAME, named after the robot)")
        ->type_name("DIR");
    a_->app->add_flag("--defaults", a_->defaults,
                      "Ask nothing: take every default (an 8-module snake on a flat floor)");
    a_->app->footer(
        "Every question has a default that Enter takes. The answers become files in the project\n"
        "folder (robot.xml, actuation.xml, environment.xml, simulation.xml, controllers/, "
        "run.lua),\n"
        "then the simulation runs. Nothing is written until the last answer. See docs/console.md.");
}

NewCommand::~NewCommand() = default;

bool NewCommand::chosen() const {
    return a_->app->parsed();
}

namespace {

// The folder the project goes into, `dir` as given (a trailing '/' dropped, a symbolic link to
// an empty folder followed), or Error when it is taken or cannot be made there: it must not
// exist, or be an empty folder; the folders it goes into that do not exist are made, inside the
// nearest one that does, which must be a folder the user can write in.
fs::path destination(fs::path dir) {
    const std::string given = dir.string();
    if (!dir.has_filename() && dir.has_parent_path()) dir = dir.parent_path();
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(dir, ec))) {
        const fs::path target = fs::read_symlink(dir, ec);
        if (!fs::exists(dir, ec)) {
            throw Error(
                fmt::format("{} is a symbolic link to {}, which does not exist: choose "
                            "another folder",
                            given, target.string()));
        }
        if (empty_folder(dir)) dir = fs::canonical(dir);  // the project goes into the target
    }
    if (fs::exists(dir, ec) && !empty_folder(dir)) {
        throw Error(fmt::format("{} exists and is not {}: choose another folder", given,
                                fs::is_directory(dir, ec) ? "empty" : "a folder"));
    }
    fs::path up = fs::absolute(dir).parent_path();
    while (!fs::exists(up, ec) && up.has_relative_path())
        up = up.parent_path();
    if (!fs::is_directory(up, ec)) {
        throw Error(
            fmt::format("cannot create {}: {} is a file, not a folder", given, up.string()));
    }
    if (::access(up.c_str(), W_OK | X_OK) != 0) {
        throw Error(fmt::format("cannot create {}: cannot write in {} ({})", given, up.string(),
                                std::strerror(errno)));
    }
    // the system may still refuse what access() allows (/proc, /sys, a read-only mount, and
    // root, to whom access() says yes): make a folder there and take it away again, so the
    // answers are never asked for a project that cannot be written
    std::string probe = (up / ".gaitlab-new-XXXXXX").string();
    if (!::mkdtemp(probe.data())) {
        throw Error(fmt::format("cannot create {}: cannot make a folder in {} ({})", given,
                                up.string(), std::strerror(errno)));
    }
    ::rmdir(probe.c_str());
    return dir;
}

// "wrote ..." lines and the run; returns the exit status
int write_and_run(Wizard& wizard, const Project& p, PartMaker& maker, const fs::path& dir,
                  bool open_editor) {
    // built in a hidden folder beside the project, renamed at the end
    const fs::path parent = fs::absolute(dir).parent_path();
    {
        std::error_code ec;
        fs::create_directories(parent, ec);
        if (ec) {
            throw IoError(fmt::format("{}: cannot create the folder {}: {}", dir.string(),
                                      parent.string(), ec.message()));
        }
    }
    std::string pattern = (parent / ("." + dir.filename().string() + ".new-XXXXXX")).string();
    if (!::mkdtemp(pattern.data())) {
        throw IoError(fmt::format("{}: cannot create the project folder: {}", dir.string(),
                                  std::strerror(errno)));
    }
    const fs::path tmp(pattern);
    struct Cleanup {
        fs::path path;
        ~Cleanup() {
            std::error_code ec;
            if (!path.empty()) fs::remove_all(path, ec);
        }
    } cleanup{tmp};

    const auto in = [&](const std::string& name) { return (tmp / name).string(); };
    if (!wizard.new_controllers().empty() || !wizard.copied_templates().empty())
        fs::create_directories(tmp / "controllers");
    for (const auto& [file, def] : wizard.new_controllers())
        maker.write_new_controller(def, in(file));
    std::set<std::string> copied;
    for (const auto& [file, name] : wizard.copied_templates()) {
        if (copied.insert(file).second) maker.write_template(name, in(file));
    }
    check_signal("writing the project");
    maker.write_robot(p.robot, in("robot.xml"));
    std::vector<GroupChoice> groups = p.groups;
    for (GroupChoice& g : groups) {
        if (g.controller.kind == ControllerChoice::Kind::file)
            g.controller.name = in(g.controller.name);
    }
    maker.write_actuation(in("robot.xml"), groups, in("actuation.xml"));
    maker.write_world(p.world, in("environment.xml"));
    maker.write_sim(p.sim, in("robot.xml"), in("actuation.xml"), in("environment.xml"),
                    in("simulation.xml"));
    write_file_atomic(
        in("run.lua"),
        "-- run.lua: made by `gaitlab new`. Runs the simulation of this folder and says how far\n"
        "-- the robot moved:  gaitlab run run.lua   (or: gaitlab run simulation.xml)\n"
        "local sim, setup = assert(gaitlab.simulation.load(\"simulation.xml\"))\n"
        "sim:run(setup.duration)\n"
        "for name, robot in pairs(setup.robots) do\n"
        "  local d = robot:displacement()\n"
        "  print(string.format(\"%s: moved %.3f m (x %.3f, y %.3f) in %g s\", name, d:norm(), "
        "d.x, d.y,\n"
        "    sim.time))\n"
        "end\n");
    check_signal("writing the project");
    // the folder as the user's umask says (mkdtemp made it private)
    const mode_t mask = ::umask(0);
    ::umask(mask);
    fs::permissions(tmp, static_cast<fs::perms>(0777 & ~mask));
    std::error_code ec;
    fs::rename(tmp, dir, ec);
    if (ec) {
        throw IoError(
            fmt::format("{}: cannot create the project folder: {}", dir.string(), ec.message()));
    }
    cleanup.path.clear();

    const std::string d = dir.string();
    std::string list = fmt::format("\nWrote {}/:\n", d);
    const auto line = [&](const std::string& file, const std::string& what) {
        list += fmt::format("  {:<34} {}\n", (dir / file).string(), what);
    };
    line("robot.xml", fmt::format("the robot: {}, {} modules, {}", p.robot.name, p.robot.modules,
                                  p.robot.connection));
    line("actuation.xml", "which controller drives which joints");
    line("environment.xml", fmt::format("the world: {}", p.world.preset));
    line("simulation.xml",
         fmt::format("the simulation: {} s, {}recording {}", number_text(p.sim.duration),
                     p.sim.solver_iterations == SimulationOptions{}.solver_iterations
                         ? ""
                         : fmt::format("{} solver iterations per step, ", p.sim.solver_iterations),
                     p.sim.record ? "on" : "off"));
    std::string edit;
    for (const auto& [file, def] : wizard.new_controllers()) {
        line(file, "your controller: write its step()");
        if (edit.empty()) edit = (dir / file).string();
    }
    for (const auto& [file, name] : wizard.copied_templates())
        line(file, "the " + name + " template, yours to change");
    line("run.lua", "runs it all: gaitlab run " + shell_word((dir / "run.lua").string()));
    say(list);

    const char* editor = std::getenv("EDITOR");
    if (open_editor && !edit.empty() && editor && *editor) {
        say(fmt::format("\nOpening {} in {} (the simulation runs when you close it)...\n", edit,
                        editor));
        const pid_t pid = ::fork();
        if (pid == 0) {
            ::execl("/bin/sh", "sh", "-c", "$EDITOR \"$1\"", "gaitlab-editor", edit.c_str(),
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
        int status = 0;
        while (pid > 0 && ::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        // Ctrl-C in the editor was the editor's
        if (g_signal == SIGINT) g_signal = 0;
    }
    check_signal("running the simulation");

    say(fmt::format("\nRunning the simulation ({} s simulated)...\n", number_text(p.sim.duration)));
    std::string error;
    std::vector<std::string> folders;
    {
        scripting::LuaHost host;
        scripting::RecordSettings rec;
        rec.by_default = true;
        rec.disabled = !p.sim.record;
        rec.root = (dir / "runs").string();
        rec.name = folder_name(p.robot.name);
        rec.script = (dir / "run.lua").string();
        rec.command = "gaitlab new";
        host.set_recording(rec);
        host.set_args(rec.script, {});
        g_host.store(&host);
        if (g_signal != 0) host.interrupt(g_signal);
        try {
            host.run_file(rec.script);
        } catch (const std::exception& e) {
            error = e.what();
        }
        try {
            host.finish(error);
        } catch (const std::exception& e) {
            if (error.empty()) error = e.what();
        }
        g_host.store(nullptr);
        folders = host.run_folders();
    }
    std::fflush(stdout);
    if (g_signal != 0) {
        print_message(stderr,
                      "gaitlab: interrupted; the project is complete in %s (run it again: "
                      "gaitlab run %s)\n",
                      d.c_str(), shell_word(d + "/run.lua").c_str());
        return 128 + g_signal;
    }
    if (!error.empty()) {
        report_line(error);
        return 1;
    }
    for (const std::string& f : folders) {
        say(fmt::format("The recording is in {} (see its series: gaitlab data {} --list)\n", f,
                        shell_word(f)));
    }
    say(fmt::format("Run it again: gaitlab run {}\n", shell_word(d + "/run.lua")));
    return 0;
}

}  // namespace

int NewCommand::run() {
    Args& a = *a_;
    for (const std::string& arg : a.app->remaining()) {
        print_message(stderr,
                      "gaitlab: unexpected argument '%s' for 'gaitlab new' (see 'gaitlab "
                      "new --help')\n",
                      arg.c_str());
        return 2;
    }
    catch_signals();
    Prompter in(a.defaults);
    try {
        // a folder that cannot be made is refused before the first question, not after the last
        fs::path dir;
        if (!a.dir.empty()) {
            dir = destination(a.dir);
        } else {
            // the project goes into the current folder
            if (::access(".", W_OK | X_OK) != 0) {
                throw Error(
                    fmt::format("cannot create the project folder in the current folder "
                                "{}: {} (give another: gaitlab new DIR)",
                                fs::current_path().string(), std::strerror(errno)));
            }
        }
        PartMaker maker;
        Wizard wizard(in, maker);
        const Project p = wizard.ask();
        if (dir.empty()) {
            // ./NAME, or NAME-2, NAME-3 ... when that is taken
            const std::string base = folder_name(p.robot.name);
            dir = base;
            std::error_code ec;
            for (int n = 2; fs::exists(fs::symlink_status(dir, ec)) && !empty_folder(dir); ++n)
                dir = fmt::format("{}-{}", base, n);
        }
        dir = destination(dir);
        return write_and_run(wizard, p, maker, dir, in.tty() && !in.defaults());
    } catch (const Stopped& s) {
        if (s.signal != 0) {
            print_message(stderr, "\ngaitlab: interrupted (%s); nothing was written\n",
                          s.signal == SIGINT    ? "SIGINT"
                          : s.signal == SIGTERM ? "SIGTERM"
                                                : "SIGHUP");
            return 128 + s.signal;
        }
        print_message(stderr, "gaitlab: end of input at '%s'; nothing was written\n",
                      s.question.c_str());
        return 1;
    } catch (const TooLong& t) {
        print_message(stderr,
                      "\ngaitlab: the answer to '%s' is longer than %zu bytes; nothing was "
                      "written\n",
                      t.question.c_str(), kMaxAnswer);
        return 1;
    } catch (const Refused& r) {
        print_message(stderr,
                      "gaitlab: %d answers to '%s' were refused in a row (see the '!' lines); "
                      "nothing was written\n",
                      r.count, r.question.c_str());
        return 1;
    } catch (const std::exception& e) {
        print_message(stderr, "gaitlab: new: %s\n", e.what());
        return 1;
    }
}

}  // namespace gaitlab::cli
