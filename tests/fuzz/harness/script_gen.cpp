// The grammar of generated scripts. A script is a list of statements, each run in its own pcall
// so that one rejected call does not end the script. Statements keep what they make in global
// slots (R[1..3] robots, W worlds, S simulations ...) that later statements, and the step
// functions of controllers, take their arguments from: so objects are reused, used after
// their simulation is gone, passed where another type is expected, and called in odd orders.
// Arguments are plausible values, with a probability set by the script's first byte replaced
// by hostile ones (NaN, infinities, 2^63, wrong types, odd strings, tables whose metamethods
// fail or loop, deep nesting).
//
// The same bytes must give the same script whichever compiler built the generator (the replay
// test is built with gcc, the fuzzer with clang), and C++ leaves the order in which the operands
// of `a() + b()` are evaluated open: every string made of several choices is therefore built
// with cat({...}), whose elements are evaluated in order.
#include "script_gen.h"

#include <cstdio>
#include <initializer_list>
#include <string_view>

namespace gaitlab::fuzz {

namespace {

// the input, read as a sequence of choices
class Choices {
  public:
    Choices(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
    bool done() const { return pos_ >= size_; }
    unsigned byte() { return pos_ < size_ ? data_[pos_++] : 0u; }
    /// A number in [0, n).
    unsigned below(unsigned n) {
        if (n <= 1) return 0;
        if (n <= 256) return byte() % n;
        const unsigned high = byte();
        return ((high << 8) | byte()) % n;
    }
    /// True once in `n` times.
    bool one_in(unsigned n) { return below(n) == 0; }
    /// One of the list's entries.
    template <class T, std::size_t N>
    const T& pick(const T (&list)[N]) {
        return list[below(static_cast<unsigned>(N))];
    }

  private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
};

// the parts, in order (a braced list is evaluated from left to right)
std::string cat(std::initializer_list<std::string> parts) {
    std::string out;
    for (const std::string& p : parts)
        out += p;
    return out;
}

// `fn(args)`
std::string call(const char* fn, const std::string& args) {
    return std::string(fn) + "(" + args + ")";
}

// `s` with what would make it a path out of the run folder taken out: a leading '/' and ".."
// components (odd strings may land where a path is expected)
std::string contained(const std::string& s) {
    std::string out;
    size_t i = 0;
    while (i <= s.size()) {
        size_t j = s.find('/', i);
        if (j == std::string::npos) j = s.size();
        const std::string part = s.substr(i, j - i);
        out += part == ".." ? "._" : part;
        if (j < s.size()) out += '/';
        i = j + 1;
    }
    if (!out.empty() && out[0] == '/') out.insert(0, "_");
    return out;
}

// a Lua string literal with `s` as its value: bytes outside printable ASCII, quotes,
// backslashes and ']' (so that generated code can sit in long brackets) as decimal escapes
std::string quote(std::string_view s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c < 32 || c > 126 || c == '"' || c == '\\' || c == ']') {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\%03u", c);
            out += buf;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out + "\"";
}

// the marker file that a shell command hidden in a generated string creates: the harness
// checks that it never appears (gaitlab must never run a command written in a name or path)
constexpr const char* kInject = "gaitlab_injected";

constexpr const char* kHostileNumbers[] = {"0/0",
                                           "1/0",
                                           "-1/0",
                                           "2^31",
                                           "2^31-1",
                                           "-2^31",
                                           "2^32+30",
                                           "2^53",
                                           "2^63",
                                           "-2^63",
                                           "math.maxinteger",
                                           "math.mininteger",
                                           "1e308",
                                           "-1e308",
                                           "5e-324",
                                           "-0.0",
                                           "1e-9",
                                           "0",
                                           "-1",
                                           "1e6",
                                           "1e9",
                                           "0xffffffff",
                                           "'12'",
                                           "' 3 '",
                                           "'0x10'",
                                           "'nan'",
                                           "'1e999'",
                                           "-180.5",
                                           "1e-300",
                                           "2^1023*1.999"};

constexpr const char* kWords[] = {
    "snake",  "robot", "pitch",  "yaw",    "all",    "roll", "y1",     "cube",    "sine",
    "offset", "hopf",  "joint3", "imu1",   "front",  "back", "x",      "angle",   "time",
    "joints", "name",  "set",    "params", "values", "step", "script", "console", "viewer"};

// names that would leave the run folder if gaitlab made paths of them: name() gives them, in
// the places of names only (any string may be given as a path, and a script that names a path
// outside its folder is refused, not a finding)
constexpr const char* kEscapingNames[] = {"..", "../../gaitlab_escape", "/tmp/gaitlab_escape",
                                          "a/../../../gaitlab_escape", "../"};

constexpr const char* kOddStrings[] = {"",
                                       ".",
                                       "a/b",
                                       "`touch gaitlab_injected`",
                                       "$(touch gaitlab_injected)",
                                       ";touch gaitlab_injected;",
                                       "a\"b",
                                       "a'b",
                                       "a\nb",
                                       "x\r\n",
                                       "\t",
                                       "\xff\xfe",
                                       "\xc3\x28",
                                       "\xf0\x9f\x98\x80",
                                       "%s%s%n%d",
                                       "{}{0}",
                                       "<x a=\"1\"/>",
                                       "&amp;&",
                                       "]]",
                                       "--",
                                       "snake.angle[*]",
                                       "sine.*",
                                       "*",
                                       "?",
                                       "[",
                                       "NaN",
                                       "inf",
                                       "with space",
                                       "UPPER",
                                       "a.b",
                                       "robot.xml"};

// a string with a NUL inside, which C code that takes char* sees cut short
constexpr std::string_view kNulString("ab\0cd", 5);

constexpr const char* kFileNames[] = {"r.xml",
                                      "robot.xml",
                                      "w.xml",
                                      "world.xml",
                                      "sim.xml",
                                      "a.xml",
                                      "x.urdf",
                                      "c.lua",
                                      "ctl.lua",
                                      "out.png",
                                      "x.csv",
                                      "run1",
                                      "runs/a",
                                      "x",
                                      "plot.png",
                                      "sub/f.xml",
                                      "sub",
                                      "",
                                      ".",
                                      "./",
                                      "a//b.xml",
                                      "dir/",
                                      "w.lua",
                                      "e.environment.xml",
                                      "controllers/my_sine.lua",
                                      "controllers/shuttle.lua",
                                      "walk.xml",
                                      "terrain.png",
                                      "robots/inchworm.urdf",
                                      "walk/snake.robot.xml",
                                      "walk/snake.actuation.xml",
                                      "walk/flat.environment.xml"};

constexpr const char* kOddFileNames[] = {"a\nb.xml",
                                         "`touch gaitlab_injected`.png",
                                         "$(touch gaitlab_injected).xml",
                                         "'q'.png",
                                         "\"q\".png",
                                         "\xc3\xa9.xml",
                                         "\xff.xml",
                                         "sp ace.png",
                                         "a%s.csv",
                                         "-n.png",
                                         ";x;.csv",
                                         ".png",
                                         "x.PNG",
                                         "x.png.png",
                                         "nul\x01.xml",
                                         "a\\b.xml",
                                         "*.xml",
                                         "~/x.xml"};

constexpr const char* kBuiltins[] = {"sine",     "offset",      "phase_chain",   "hopf",
                                     "matsuoka", "distributed", "hindmarsh_rose"};
constexpr const char* kParamNames[] = {"amplitude", "frequency", "phase", "phase0", "offset",
                                       "angle",     "coupling",  "gain",  "seed"};
constexpr const char* kPresets[] = {"flat",   "slippery", "sticky", "ramp",
                                    "stairs", "pipe",     "rubble", "hills"};
constexpr const char* kSensorKinds[] = {"joint", "imu", "contact", "range", "position"};
constexpr const char* kChannels[] = {"angle", "velocity", "torque", "roll", "pitch",
                                     "yaw",   "qw",       "ax",     "wz",   "contact",
                                     "force", "distance", "hit",    "x",    "vz"};
constexpr const char* kSeries[] = {"snake.com.*", "snake.angle[*]", "sine.*",  "robot",
                                   "controller",  "sensor",         "*.com.x", "snake.energy",
                                   "robot.com.x", "sine.amplitude", "*",       "nothing"};
constexpr const char* kRunFiles[] = {"run.json",   "series.csv", "data.csv",
                                     "events.csv", "log.txt",    "config/script.lua"};
// what a damaged file gets at the place it is cut
constexpr const char* kSplices[] = {
    ",",       "\n",    "\"",   "{",    "}",    "[",           "]",       ":",
    "1e999",   "-",     "nan",  "<",    "/>",   "</",          "<robot>", "=",
    "\"\"",    "\r\n",  ",,,,", "\n\n", "null", "true",        "-0",      "999999999999999999999",
    "\\u0000", "0x1p4", "&#0;", "<!--", "\t",   "\xef\xbb\xbf"};
// every reader given the damaged file at `path`, and its run folder opened
constexpr const char* kReadBack =
    "for _, load in ipairs{ gaitlab.robot.load, gaitlab.world.load, gaitlab.simulation.load, "
    "gaitlab.actuation.load, gaitlab.robot.load_urdf } do pcall(load, path) end "
    "local run = gaitlab.data.open(path:match('^(.*)/[^/]*$') or '.') "
    "if run then D[1] = run local list = run:series() run:events() run:log() "
    "if list[1] then run:get(list[1].name) run:export{ series = { list[1].name }, file = "
    "'export.csv' } end end";
constexpr const char* kSlots[] = {"R", "W", "G", "C", "K", "S", "N",
                                  "M", "A", "D", "L", "X", "T", "P"};
constexpr const char* kMethods[] = {
    "group",  "position",       "bodies", "save",   "actuate",     "sensor",
    "drive",  "joints",         "add",    "box",    "heightfield", "triangles",
    "run",    "step",           "reset",  "record", "live",        "objects",
    "params", "values",         "set",    "read",   "on",          "off",
    "get",    "series",         "export", "plot",   "groups",      "norm",
    "flush",  "channels",       "play",   "pause",  "status",      "heading",
    "turned", "check_accuracy", "energy"};

constexpr const char* kSetupWorld =
    "try(function() R[1] = gaitlab.robot.chain{ name = 'snake', modules = 4, connection = "
    "'pitch-yaw' } W[1] = gaitlab.world{} W[1]:add(R[1]) G[1] = R[1]:group('pitch') "
    "G[2] = R[1]:group('yaw') end)\n";
constexpr const char* kSetupDrive =
    "try(function() C[1] = G[1]:drive(gaitlab.controllers.sine{}) N[1] = R[1]:sensor{ kind = "
    "'imu', module = 2 } end)\n";
constexpr const char* kSetupSimulation =
    "try(function() S[1] = gaitlab.simulation{ world = W[1] } S[1]:step(30) end)\n";
constexpr const char* kSetupRecording =
    "try(function() S[1] = gaitlab.simulation{ world = W[1], record = 'runs/setup' } "
    "S[1]:step(30) end)\n";

class Generator {
  public:
    Generator(const std::uint8_t* data, std::size_t size) : in_(data, size) {}

    std::string script() {
        // how often arguments are hostile: from never to more often than not
        hostility_ = in_.below(9);
        // rarely, an error with an odd value ends the script (the host's message handler)
        const bool raise_at_end = in_.one_in(16);
        std::string out =
            "R, W, G, C, K, S, N, M, A, D, L, X, T, P = "
            "{}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}\n"
            "local function try(f, ...) return pcall(f, ...) end\n";
        // most scripts start from a robot in a world, or a running simulation, so that the
        // statements after reach further than argument checks
        const unsigned setup = in_.below(4);
        if (setup >= 1) out += kSetupWorld;
        if (setup >= 2) out += kSetupDrive;
        if (setup == 2) out += kSetupSimulation;
        if (setup == 3) out += kSetupRecording;
        int count = 0;
        while (!in_.done() && count < kMaxStatements) {
            out += cat({"try(function()\n", statement(0), "\nend)\n"});
            ++count;
        }
        if (raise_at_end) out += cat({"error(", value(), ")\n"});
        return out;
    }

  private:
    static constexpr int kMaxStatements = 160;
    static constexpr int kMaxDepth = 3;    // statements inside statements
    static constexpr int kMaxNesting = 4;  // values inside values

    bool hostile() { return in_.below(16) < hostility_; }
    // slot 1 half of the time: statements meet the objects others made
    std::string slot() {
        const unsigned b = in_.below(4);
        return std::to_string(b < 2 ? 1 : b);
    }
    std::string ref(const char* table) { return cat({table, "[", slot(), "]"}); }
    std::string x_slot() { return ref("X"); }

    // ---- values ---------------------------------------------------------------------------

    std::string number() {
        switch (in_.below(6)) {
            case 0:
                return in_.pick(kHostileNumbers);
            case 1:
                return std::to_string(static_cast<int>(in_.byte()) - 16);
            case 2: {
                const int a = static_cast<int>(in_.byte()) - 128;
                return cat({"(", std::to_string(a), "/", std::to_string(in_.byte() + 1), ")"});
            }
            case 3:
                return cat({std::to_string(in_.byte() % 4), ".", std::to_string(in_.byte())});
            case 4:
                return cat({"-", std::to_string(in_.byte() % 8), ".", std::to_string(in_.byte())});
            default:
                return cat({"(", number(), in_.one_in(2) ? " * " : " + ", number(), ")"});
        }
    }

    // a number in [lo, hi] most of the time, anything otherwise
    std::string real(double lo, double hi) {
        if (hostile()) return value();
        const double t = in_.byte() / 255.0;
        char buf[48];
        std::snprintf(buf, sizeof buf, "%.6g", lo + t * (hi - lo));
        return buf;
    }

    std::string integer(int lo, int hi) {
        if (hostile()) return value();
        return std::to_string(lo + static_cast<int>(in_.below(static_cast<unsigned>(hi - lo + 1))));
    }

    std::string odd_string() {
        switch (in_.below(7)) {
            case 0:
                return quote(kNulString);
            case 1: {  // bytes of the input itself
                std::string s;
                for (unsigned n = in_.below(17); n > 0; --n)
                    s += static_cast<char>(in_.byte());
                return quote(contained(s));
            }
            case 2: {
                const std::string word = quote(in_.pick(kWords));
                const unsigned a = in_.byte();
                const unsigned b = in_.byte();
                const unsigned count = in_.one_in(8) ? 1 + a * b * 16 : 1 + a * b / 8;
                return cat({"string.rep(", word, ", ", std::to_string(count), ")"});
            }
            case 3: {
                const std::string first = in_.pick(kOddStrings);
                return quote(contained(first + in_.pick(kOddStrings)));
            }
            default:
                return quote(in_.pick(kOddStrings));
        }
    }

    std::string string_value() { return in_.one_in(2) ? quote(in_.pick(kWords)) : odd_string(); }

    // a name for a robot, sensor, module, controller ...: a plausible word, or anything
    std::string name() {
        if (!hostile()) return quote(in_.pick(kWords));
        switch (in_.below(4)) {
            case 0:
                return value();
            case 1:
                return quote(in_.pick(kEscapingNames));
            default:
                return odd_string();
        }
    }

    // a path relative to the run folder that never leaves it
    std::string path() {
        switch (in_.below(hostile() ? 8 : 6)) {
            case 0:
                return ref("P");
            case 1:
                return quote(std::string("sub/") + in_.pick(kFileNames));
            case 6:
                return quote(in_.pick(kOddFileNames));
            case 7: {
                const std::string dirs(in_.byte() % 4 + 1, 'd');
                return quote(dirs + "/" + std::string(in_.byte() + 1, 'n') + ".xml");
            }
            default:
                return quote(in_.pick(kFileNames));
        }
    }

    std::string vec() {
        if (hostile()) return value();
        switch (in_.below(4)) {
            case 0:
                return cat(
                    {"{ x = ", real(-1, 1), ", y = ", real(-1, 1), ", z = ", real(0, 1), " }"});
            case 1:
                return cat(
                    {"gaitlab.vec3(", real(-1, 1), ", ", real(-1, 1), ", ", real(0, 1), ")"});
            default:
                return cat({"{ ", real(-1, 1), ", ", real(-1, 1), ", ", real(0, 1), " }"});
        }
    }

    std::string object() { return ref(in_.pick(kSlots)); }

    // a table whose metamethods misbehave
    std::string hostile_table() {
        switch (in_.below(22)) {
            case 0:
                return "setmetatable({}, { __index = function() error('index') end })";
            case 1:
                return "setmetatable({}, { __index = function(t, k) return t[k] end })";
            case 2:
                return "setmetatable({}, { __len = function() error('len') end })";
            case 3:
                return cat(
                    {"setmetatable({1, 2}, { __len = function() return ", number(), " end })"});
            case 4:
                return "setmetatable({}, { __newindex = function() error('newindex') end })";
            case 5:
                return in_.one_in(4)
                           ? "setmetatable({}, { __index = function() while true do end end })"
                           : "setmetatable({}, { __index = function() for i = 1, 1e5 do end end })";
            case 6:
                return cat({"setmetatable({1, 2, 3}, { __index = function(t, k) return ", value(),
                            " end })"});
            case 7:
                return "setmetatable({}, { __gc = function() error('gc') end })";
            case 8:
                return "setmetatable({}, { __gc = function(o) X[1] = o; collectgarbage() end })";
            case 9:
                return "setmetatable({}, { __tostring = function() error('tostring') end })";
            case 10:
                return cat({"setmetatable({}, { __tostring = function() return ", value(),
                            " end, __name = ", name(), " })"});
            case 11:
                return "setmetatable({}, { __name = 'gaitlab.Robot' })";
            case 12:
                return cat({"setmetatable({}, { __index = ", any_fields(), " })"});
            case 13:
                return "{ 1, nil, 3, nil, 5 }";
            case 14:
                return "{ [2^31] = 1, [0] = 2, [-1] = 3, [1.5] = 4, [true] = 5 }";
            case 15:
                return "(function() local t = {} t[1] = t t.x = t t.name = t return t end)()";
            case 16: {
                // nested in the source (the parser allows about 200 levels), or built at run time
                const unsigned d = in_.byte();
                if (d < 128) return std::string(d + 1, '{') + "1" + std::string(d + 1, '}');
                return cat({"(function() local t = 1 for i = 1, ", std::to_string(d * d * 4),
                            " do t = { t, x = t } end return t end)()"});
            }
            case 17: {
                const unsigned a = in_.byte();
                const unsigned b = in_.byte();
                return cat({"(function() local t = {} for i = 1, ", std::to_string(1 + a * b * 2),
                            " do t[i] = ", value(), " end return t end)()"});
            }
            case 18:
                return "setmetatable({}, { __index = function(t, k) return setmetatable({}, "
                       "getmetatable(t)) end })";
            case 19:
                return "setmetatable({}, { __eq = error, __lt = error, __le = error, __concat = "
                       "error, __call = error, __unm = error })";
            case 20:
                return cat({"setmetatable({}, { __metatable = ", value(), " })"});
            default:
                return cat({"setmetatable({ ", value(),
                            " }, { __index = function(t, k) error(setmetatable({}, { __tostring = "
                            "function() error('deep') end })) end })"});
        }
    }

    // any value: the wrong types every argument must survive
    std::string value() {
        if (nesting_ >= kMaxNesting) return number();
        ++nesting_;
        std::string v;
        switch (in_.below(16)) {
            case 0:
            case 1:
            case 2:
                v = number();
                break;
            case 3:
            case 4:
                v = string_value();
                break;
            case 5:
                v = in_.pick({"nil", "true", "false", "{}"});
                break;
            case 6:
            case 7:
                v = hostile_table();
                break;
            case 8:
                v = in_.pick({"function() end", "function() error('boom') end",
                              "function(...) return ... end", "print", "error",
                              "coroutine.create(function() end)", "io.stdout", "gaitlab",
                              "gaitlab.robot", "math.huge", "_G"});
                break;
            case 9:
            case 10:
            case 11:
                v = object();
                break;
            case 12:
                v = cat({"{ ", value(), ", ", value(), " }"});
                break;
            case 13:
                v = cat({"{ ", in_.pick(kWords), " = ", value(), " }"});
                break;
            case 14:
                v = cat({"gaitlab.vec3(", number(), ", ", number(), ", ", number(), ")"});
                break;
            default:
                v = any_fields();
                break;
        }
        --nesting_;
        return v;
    }

    // ---- tables of named fields -----------------------------------------------------------

    // `{ key = value, ... }` with each key present or not (a key written "!key" is required:
    // present unless hostile); the values plausible or hostile, sometimes an unknown key or a
    // positional value; sometimes the table hides behind __index, or is no table at all
    template <class F>
    std::string fields(std::initializer_list<const char*> keys, F&& plausible) {
        if (hostile() && in_.one_in(3)) return value();
        std::string body;
        for (const char* key : keys) {
            const bool required = key[0] == '!';
            const char* k = required ? key + 1 : key;
            if (required ? hostile() && in_.one_in(2) : in_.one_in(2)) continue;
            const std::string v = hostile() ? value() : plausible(std::string_view(k));
            body += cat({k, " = ", v, ", "});
        }
        if (hostile()) {
            switch (in_.below(5)) {
                case 0:
                    body += cat({in_.pick(kWords), " = ", value(), ", "});
                    break;
                case 1:
                    body += cat({value(), ", "});
                    break;
                case 2:
                    body += cat({"[", value(), "] = ", value(), ", "});
                    break;
                default:
                    break;
            }
        }
        const std::string table = "{ " + body + "}";
        if (hostile() && in_.one_in(3)) return "setmetatable({}, { __index = " + table + " })";
        return table;
    }

    std::string any_fields() {
        return fields({"name", "modules", "world", "kind", "friction", "size", "dt"},
                      [&](std::string_view) { return real(0, 4); });
    }

    std::string chain_args() {
        return fields({"name", "!modules", "connection", "module"}, [&](std::string_view k) {
            if (k == "name") return name();
            if (k == "modules") return integer(1, 10);
            if (k == "connection") {
                return quote(in_.pick({"pitch-pitch", "pitch-yaw", "yaw-yaw", "pitch-roll"}));
            }
            return in_.one_in(2) ? quote(in_.pick({"y1", "cube"})) : ref("M");
        });
    }

    std::string world_args() {
        return fields({"floor", "gravity"}, [&](std::string_view k) {
            if (k == "gravity") return vec();
            return in_.one_in(4) ? std::string("false") : "{ friction = " + real(0, 1) + " }";
        });
    }

    std::string pose() {
        return fields({"x", "y", "z", "yaw", "pitch", "roll"}, [&](std::string_view k) {
            if (k == "x" || k == "y") return real(-1, 1);
            if (k == "z") return real(0, 0.2);
            return real(-180, 180);
        });
    }

    // the keys that world objects have
    std::string object_field(std::string_view k) {
        if (k == "position" || k == "size" || k == "direction") return vec();
        if (k == "yaw") return real(-180, 180);
        if (k == "friction") return real(0, 1);
        if (k == "mass") return real(0, 0.5);
        if (k == "lying") return in_.one_in(2) ? "true" : "false";
        if (k == "steps" || k == "sides" || k == "count" || k == "samples") return integer(0, 24);
        if (k == "seed") return integer(0, 5);
        if (k == "slope") return real(0, 50);
        if (k == "image") return in_.one_in(2) ? std::string("\"terrain.png\"") : path();
        if (k == "heights") {
            switch (in_.below(4)) {
                case 0:
                    return "function(x, y) return 0.01 * x end";
                case 1:
                    return cat({"function(x, y) return ", value(), " end"});
                case 2:
                    return "{ { 0, 0.01 }, { 0.02, 0 } }";
                default:
                    return cat(
                        {"{ { ", real(0, 0.1), ", ", real(0, 0.1), " }, { ", real(0, 0.1), " } }"});
            }
        }
        return real(0.001, 1);
    }

    std::string world_object() {
        const auto f = [&](std::string_view k) { return object_field(k); };
        switch (in_.below(8)) {
            case 0:
                return call("box", fields({"size", "position", "yaw", "mass", "friction"}, f));
            case 1:
                return call(
                    "wall",
                    fields({"length", "height", "thickness", "position", "yaw", "friction"}, f));
            case 2:
                return call("ramp",
                            fields({"slope", "length", "width", "position", "yaw", "friction"}, f));
            case 3:
                return call("stairs", fields({"steps", "step_height", "step_depth", "width",
                                              "landing", "position", "yaw", "friction"},
                                             f));
            case 4:
                return call("cylinder", fields({"radius", "length", "lying", "position", "yaw",
                                                "mass", "friction"},
                                               f));
            case 5:
                return call("pipe", fields({"radius", "thickness", "length", "sides", "position",
                                            "yaw", "friction"},
                                           f));
            case 6:
                return call("rubble", fields({"length", "width", "count", "min_size", "max_size",
                                              "min_height", "max_height", "seed", "position", "yaw",
                                              "friction"},
                                             f));
            default:
                return call("heightfield",
                            fields({"length", "width", "heights", "image", "max_height", "samples",
                                    "resolution", "position", "yaw", "friction"},
                                   f));
        }
    }

    std::string preset_args(std::string_view preset) {
        const auto f = [&](std::string_view k) {
            if (k == "steps" || k == "sides" || k == "count" || k == "seed") return integer(0, 30);
            if (k == "friction") return real(0, 1);
            if (k == "slope") return real(0, 50);
            return real(0.001, 3);
        };
        if (preset == "ramp") return fields({"slope", "length", "width", "top", "friction"}, f);
        if (preset == "stairs") {
            return fields(
                {"steps", "step_height", "step_depth", "width", "landing", "distance", "friction"},
                f);
        }
        if (preset == "pipe") {
            return fields({"radius", "thickness", "length", "sides", "entrance", "friction"}, f);
        }
        if (preset == "rubble") {
            return fields({"count", "length", "width", "min_size", "max_size", "min_height",
                           "max_height", "seed", "friction"},
                          f);
        }
        if (preset == "hills") {
            return fields({"height", "wavelength", "length", "width", "friction"}, f);
        }
        return fields({"friction"}, f);
    }

    std::string sensor_args() {
        return fields(
            {"!kind", "name", "joint", "module", "half", "direction", "max_range", "enabled"},
            [&](std::string_view k) {
                if (k == "kind") return quote(in_.pick(kSensorKinds));
                if (k == "name") return name();
                if (k == "joint" || k == "module") return integer(0, 9);
                if (k == "half") return quote(in_.pick({"tail", "head", "middle"}));
                if (k == "direction") return vec();
                if (k == "max_range") return real(0, 5);
                return std::string(in_.one_in(2) ? "true" : "false");
            });
    }

    std::string module_args() {
        return fields({"!name", "base", "shape", "length", "width", "height", "radius", "mass",
                       "axis", "range", "max_speed", "max_torque", "kp", "friction"},
                      [&](std::string_view k) {
                          if (k == "name") return name();
                          if (k == "base") {
                              return in_.one_in(2) ? quote(in_.pick({"y1", "cube"})) : ref("M");
                          }
                          if (k == "shape") return quote(in_.pick({"box", "cylinder", "sphere"}));
                          if (k == "axis") return quote(in_.pick({"bend", "twist", "roll"}));
                          if (k == "range") {
                              return cat({"{ ", real(-180, 0), ", ", real(0, 180), " }"});
                          }
                          if (k == "friction") return real(0, 1);
                          if (k == "max_speed") return real(1, 500);
                          if (k == "kp" || k == "max_torque") return real(0.01, 20);
                          return real(0.005, 0.2);
                      });
    }

    std::string params_args() {
        return fields({"amplitude", "frequency", "phase", "phase0", "offset", "angle", "coupling",
                       "gain", "seed", "near"},
                      [&](std::string_view k) {
                          if (k == "frequency") return real(0, 5);
                          if (k == "seed") return integer(0, 10);
                          return real(-90, 90);
                      });
    }

    std::string series_list() {
        if (hostile()) return value();
        std::string s = "{ ";
        for (unsigned n = in_.below(4); n > 0; --n)
            s += quote(in_.pick(kSeries)) + ", ";
        return s + "}";
    }

    std::string record_value() {
        switch (in_.below(5)) {
            case 0:
                return "false";
            case 1:
                return "true";
            case 2:
                return path();
            default:
                return fields({"dir", "record_every", "flush_seconds", "series"},
                              [&](std::string_view k) {
                                  if (k == "dir") return path();
                                  if (k == "record_every") return integer(1, 20);
                                  if (k == "flush_seconds") return real(0, 1);
                                  return series_list();
                              });
        }
    }

    std::string simulation_args() {
        return fields({"!world", "dt", "control_every", "seed", "solver_iterations",
                       "on_controller_error", "record"},
                      [&](std::string_view k) {
                          if (k == "world") return ref("W");
                          if (k == "dt") return real(0.0002, 0.01);
                          if (k == "control_every") return integer(1, 40);
                          if (k == "seed") return integer(0, 9);
                          if (k == "solver_iterations") return integer(1, 30);
                          if (k == "on_controller_error") {
                              return quote(in_.pick({"stop", "continue", "pause", "ignore"}));
                          }
                          return record_value();
                      });
    }

    // ---- controllers ----------------------------------------------------------------------

    std::string joint_index() {
        if (hostile()) return value();
        return in_.pick({"1", "2", "self.joints", "self.joints + 1", "0", "m"});
    }

    // one statement of a Lua controller's step(self, dt); `sandboxed` code (a controller file)
    // cannot see the script's slots
    std::string step_statement(int depth, bool sandboxed) {
        switch (in_.below(sandboxed ? 16 : 20)) {
            case 0:
            case 1: {
                const std::string amplitude = real(-60, 60);
                return cat({"for m = 1, self.joints do self:set_angle(m, ", amplitude,
                            " * math.sin(", std::to_string(in_.byte() % 7),
                            " * (self.n or 0) + m)) end"});
            }
            case 2:
                return cat(
                    {"local m = 1 self:set_angle(", joint_index(), ", ", real(-90, 90), ")"});
            case 3:
                return cat({"local m = 1 local a = self:",
                            in_.pick({"joint_angle", "joint_velocity", "joint_torque"}), "(",
                            joint_index(), ")"});
            case 4:
                return cat({"local s = self:sensor(", name(),
                            in_.one_in(2) ? ", " + quote(in_.pick(kChannels)) : std::string(),
                            ")"});
            case 5:
                return "self.n = (self.n or 0) + 1";
            case 6:
                return cat(
                    {"self.",
                     in_.pick({"time", "angle", "x", "phase", "joints", "amplitude", "near"}),
                     " = ", value()});
            case 7:
                return cat(
                    {"if self.time then self.time[", joint_index(), "] = ", number(), " end"});
            case 8:
                return cat({"self.", in_.pick(kParamNames), " = ", real(-90, 90)});
            case 9:
                if (in_.one_in(3)) return cat({"error(", value(), ")"});
                return cat({"if (self.n or 0) > ", std::to_string(in_.byte() % 40), " then error(",
                            value(), ") end"});
            case 10:
                return in_.one_in(3) ? "while true do end" : "for i = 1, 1e5 do end";
            case 11:
                return cat({"coroutine.yield(", value(), ")"});
            case 12:
                return "collectgarbage()";
            case 13:
                return in_.one_in(2) ? cat({"self.m = ", value()})
                                     : cat({"setmetatable(self, ", value(), ")"});
            case 14:
                // patterns whose matching backtracks a lot: the sandbox must refuse them
                return cat({"local s = string.rep('a', ", std::to_string(in_.byte() % 40),
                            "):find('",
                            in_.pick({"(a*)*b", ".-.-.-.-.-.-.-b", "a-a-a-b", "(.-)%1b"}), "')"});
            case 15:
                return cat({"do return ", value(), " end"});
            case 16:
            case 17:
            case 18:
                // anything a script does, from inside a step: reset, drive, step, record ...
                return statement(depth + 1);
            default:
                return "gaitlab.controller.reload()";
        }
    }

    std::string step_function(int depth, bool sandboxed) {
        std::string body;
        ++in_step_;
        for (unsigned n = 1 + in_.below(4); n > 0; --n)
            body += cat({"    ", step_statement(depth, sandboxed), "\n"});
        --in_step_;
        return "function(self, dt)\n" + body + "  end";
    }

    std::string class_params() {
        std::string p = "{ ";
        for (unsigned n = in_.below(3); n > 0; --n) {
            p += cat({in_.pick(kParamNames), " = { ", real(-10, 10), ", min = ", real(-90, 0),
                      ", max = ", real(0, 90), in_.one_in(2) ? ", unit = " + name() : std::string(),
                      " }, "});
        }
        return p + "}";
    }

    // the table given to gaitlab.controller{...}
    std::string class_args(int depth, bool sandboxed) {
        return fields(
            {"!name", "params", "values", "!step", "snapshot", "on_reload", "instruction_budget"},
            [&](std::string_view k) -> std::string {
                if (k == "name") return name();
                if (k == "params") return class_params();
                if (k == "values") {
                    std::string v = "{ ";
                    for (unsigned n = in_.below(3); n > 0; --n)
                        v += quote(in_.pick({"time", "angle", "x", "joints", "set"})) + ", ";
                    return v + "}";
                }
                if (k == "step") return step_function(depth, sandboxed);
                if (k == "snapshot") return "function(self) return " + value() + " end";
                if (k == "on_reload") {
                    // runs before the next step, inside the simulation's tick
                    ++in_step_;
                    const std::string body = step_statement(depth, sandboxed);
                    --in_step_;
                    return "function(self, snap) " + body + " end";
                }
                return integer(1, 100000);
            });
    }

    // a controller file's text, in long brackets: returns a class, or misbehaves
    std::string controller_file(int depth) {
        std::string code;
        switch (in_.below(8)) {
            case 0:
                code = "return 42";
                break;
            case 1:
                code = "return gaitlab.controller{ name = 'broken', step = function(self) end";
                break;
            case 2:
                // a sandboxed file reaches no processes (and the fuzzer lets no script run one)
                code =
                    cat({"pcall(os.execute, 'touch ", kInject, "') pcall(io.popen, 'touch ",
                         kInject, "') return gaitlab.controller(", class_args(depth, true), ")"});
                break;
            case 3:
                code = "while true do end";
                break;
            default:
                code = "return gaitlab.controller(" + class_args(depth, true) + ")";
                break;
        }
        return "[=====[" + code + "]=====]";
    }

    // ---- statements -----------------------------------------------------------------------

    std::string statement(int depth) {
        if (depth > kMaxDepth) return "collectgarbage('step')";
        switch (in_.below(53)) {
            case 0:
            case 1:
                return cat({ref("R"), " = gaitlab.robot.chain(", chain_args(), ")"});
            case 2:
                return cat({ref("W"), " = gaitlab.world(", world_args(), ")"});
            case 3: {
                const std::string w = ref("W");
                const std::string t = ref("T");
                const char* p = in_.pick(kPresets);
                return cat({w, ", ", t, " = gaitlab.worlds.", p, "(", preset_args(p), ")"});
            }
            case 4:
            case 5: {
                const std::string w = ref("W");
                const std::string r = ref("R");
                std::string start;
                if (in_.one_in(2)) start = ", " + (in_.one_in(2) ? ref("T") : pose());
                return cat({w, ":add(", r, start, ")"});
            }
            case 6:
                return cat({ref("W"), ":", world_object()});
            case 7: {
                const std::string g = ref("G");
                const std::string r = ref("R");
                std::string role;
                if (in_.one_in(3)) {
                    role = cat({"{ ", integer(1, 9), ", ", integer(1, 9), " }"});
                } else if (hostile()) {
                    role = value();
                } else {
                    role = quote(in_.pick({"pitch", "yaw", "roll", "all"}));
                }
                return cat({g, " = ", r, ":group(", role, ")"});
            }
            case 8:
                return cat({ref("C"), " = gaitlab.controllers.", in_.pick(kBuiltins), "(",
                            params_args(), ")"});
            case 9:
                return cat({ref("K"), " = gaitlab.controller(", class_args(depth, false), ")"});
            case 10:
                return cat(
                    {ref("C"), " = ", ref("K"), in_.one_in(2) ? "(" + params_args() + ")" : "()"});
            case 11:
            case 12:
                return cat({ref("G"), ":drive(", ref("C"), ")"});
            case 13:
                return set_param();
            case 14:
            case 15:
                return cat({ref("S"), " = gaitlab.simulation(", simulation_args(), ")"});
            case 16:
            case 17:
                return cat({ref("S"), ":step(",
                            hostile() ? value() : std::to_string(1 + in_.byte() * 2), ")"});
            case 18:
                return cat({ref("S"), ":run(", real(0, 0.5), ")"});
            case 19:
                return cat({ref("S"), ":reset()"});
            case 20:
                return recording();
            case 21:
                return live();
            case 22:
                return cat({ref("N"), " = ", ref("R"), ":sensor(", sensor_args(), ")"});
            case 23:
                return sensor_use();
            case 24:
                return cat({ref("M"), " = gaitlab.module(", module_args(), ")"});
            case 25:
                return save_and_load();
            case 26:
                return run_data();
            case 27:
                return plot_or_export();
            case 28:
            case 29:
                return query();
            case 30:
                return templates();
            case 31:
                return controller_from_file(depth);
            case 32:
                return "gaitlab.controller.reload()";
            case 33:
                return cat(
                    {"collectgarbage(",
                     quote(in_.pick({"collect", "step", "incremental", "generational", "count"})),
                     ")"});
            case 34:
                return cat({object(), " = ", in_.one_in(2) ? std::string("nil") : object()});
            case 35:
                return cat({"local co = coroutine.wrap(function() ", statement(depth + 1),
                            " coroutine.yield() ", statement(depth + 1), " end) co() ", x_slot(),
                            " = co"});
            case 36:
                return cat({"local co = ", x_slot(), " if type(co) == 'function' then co() end"});
            case 37:
                // memory pressure: later calls fail to allocate at odd places
                if (in_.one_in(3)) {
                    return "X.mem = {} for i = 1, 1e6 do X.mem[i] = string.rep('m', 4096) .. i "
                           "end";
                }
                return cat({"X.mem = X.mem or {} for i = 1, ", std::to_string(in_.byte() * 64),
                            " do X.mem[#X.mem + 1] = {} end"});
            case 38:
                return "X.mem = nil collectgarbage()";
            case 39:
                return wrong_self();
            case 40:
                return cat({"local v = gaitlab.vec3(", number(), ", ", number(), ", ", number(),
                            ") local w = v ", in_.pick({"+", "-", "*", "/", "=="}), " ", value(),
                            " ", x_slot(), " = tostring(w) .. tostring(v:norm())"});
            case 41:
                return cat({"local k = gaitlab.sensor.kinds ", x_slot(),
                            " = gaitlab.sensor.channels(",
                            hostile() ? value() : quote(in_.pick(kSensorKinds)), ")"});
            case 42:
                return cat({"print(", value(), ", ", object(), ")"});
            case 43:
                return cat({"for i = 1, ", std::to_string(1 + in_.below(6)), " do ",
                            statement(depth + 1), " end"});
            case 44:
                return cat({"local ok = pcall(function() ", statement(depth + 1), " end) ",
                            statement(depth + 1)});
            case 45:
                return preset();
            case 46:
                return robot_actuation();
            case 47:
                return cat({ref("W"), ":add(", object(), ")"});
            case 48:
                return step_inside_class(depth);
            case 49:
                return damage_file();
            case 50:
                return playback();
            case 51:
                return cat({"local s = ", ref("S"), " local st = s:status() ", x_slot(),
                            " = { tostring(st), st.time, s.playing, s.speed, s.delay, ", ref("R"),
                            ":heading(), ", ref("R"), ":turned(), ", ref("R"), ":energy() }"});
            default:
                return cat({"local t = ", ref("W"), ":triangles() ", x_slot(), " = #t"});
        }
    }

    // playing in the background (the console's sim:play; nothing pumps it here, so this
    // checks the switches, their values and what stepping does to a playing simulation)
    std::string playback() {
        const std::string sim = ref("S");
        switch (in_.below(5)) {
            case 0:
                return cat({sim, ":play()"});
            case 1:
                return cat({sim, ":pause()"});
            case 2:
                return cat({sim, ".speed = ",
                            hostile() ? value() : in_.pick({"1", "4", "0.25", "math.huge"})});
            case 3:
                return cat({sim, ".delay = ", hostile() ? value() : real(0, 0.01)});
            default:
                return cat({sim, ".playing = ", value()});
        }
    }

    // a file gaitlab wrote (a saved robot, world, simulation or actuation, a file of a run
    // folder) cut at some place, with something spliced in: the readers that load it later
    // must reject it, or read it, without crashing
    std::string damage_file() {
        std::string file;
        if (in_.one_in(2)) {
            file = ref("P");
        } else {
            const std::string s = ref("S");
            file = cat({"((", s, " and ", s, ".record_dir) or 'runs/setup') .. '/",
                        in_.pick(kRunFiles), "'"});
        }
        const unsigned a = in_.byte();
        const unsigned b = in_.byte();
        const std::string splice = in_.one_in(4) ? odd_string() : quote(in_.pick(kSplices));
        const std::string cut = std::to_string(in_.below(17));
        return cat({"local path = ", file,
                    " local f = type(path) == 'string' and io.open(path, 'rb') if f then "
                    "local s = f:read('a') f:close() local k = ",
                    std::to_string(a * 256 + b), " % (#s + 1) s = s:sub(1, k) .. ", splice,
                    " .. s:sub(k + 1 + ", cut, ") f = io.open(path, 'wb') f:write(s) f:close() ",
                    kReadBack, " end"});
    }

    // a controller whose step runs one statement of the script's grammar, driving a group at
    // once: reset, drive, record ... from inside a step
    std::string step_inside_class(int depth) {
        const std::string n = name();
        ++in_step_;
        const std::string body = statement(depth + 1);
        --in_step_;
        return cat({"local K0 = gaitlab.controller{ name = ", n, ", step = function(self) ", body,
                    " end } ", ref("G"), ":drive(K0())"});
    }

    std::string preset() {
        const std::string def =
            fields({"!name", "description", "params", "check", "!build"},
                   [&](std::string_view k) -> std::string {
                       if (k == "params") {
                           return "{ size = { 1, min = 0, max = 10, unit = 'm', doc = 'x' } }";
                       }
                       if (k == "check") return "function(p) return " + value() + " end";
                       if (k == "build") {
                           const std::string w = in_.one_in(2) ? ref("W") : "gaitlab.world{}";
                           return cat({"function(p) return ", w, ", ", value(), " end"});
                       }
                       return name();
                   });
        const std::string call = in_.one_in(2) ? "()" : "{ size = " + real(0, 12) + " }";
        return cat({"local preset = gaitlab.world.preset(", def, ") ", ref("W"), ", ", ref("T"),
                    " = preset", call});
    }

    std::string set_param() {
        switch (in_.below(4)) {
            case 0:
                return cat({ref("C"), ".", in_.pick(kParamNames), " = ", real(-90, 90)});
            case 1: {
                const std::string c = ref("C");
                const std::string p = quote(in_.pick(kParamNames));
                const std::string v = real(-90, 90);
                std::string origin;
                if (in_.one_in(2)) {
                    origin = ", " + quote(in_.pick({"script", "console", "viewer", "file", "x"}));
                }
                return cat({c, ":set(", p, ", ", v, origin, ")"});
            }
            case 2:
                // a parameter the controller has, whatever its kind
                return cat({"local c = ", ref("C"),
                            " local ks = {} for k in pairs(c:params()) do ks[#ks + 1] = k end "
                            "table.sort(ks) if #ks > 0 then c[ks[1 + ",
                            std::to_string(in_.byte()), " % #ks]] = ", real(-90, 90), " end"});
            default:
                return cat({ref("C"), "[", value(), "] = ", value()});
        }
    }

    std::string recording() {
        switch (in_.below(4)) {
            case 0:
                return cat({ref("P"), " = ", ref("S"), ":record(", record_value(), ")"});
            case 1:
                return cat({ref("S"), ":record(false)"});
            case 2:
                return cat({ref("S"), ":flush()"});
            default:
                return cat({ref("P"), " = ", ref("S"), ".record_dir"});
        }
    }

    std::string live() {
        switch (in_.below(4)) {
            case 0:
                return cat({ref("L"), " = ", ref("S"), ":live(",
                            fields({"series", "sample_every", "refresh", "size"},
                                   [&](std::string_view k) {
                                       if (k == "series") return series_list();
                                       if (k == "refresh") return real(0, 1);
                                       return integer(1, 50);
                                   }),
                            ")"});
            case 1:
                return cat({x_slot(), " = ", ref("L"), ":get(",
                            in_.one_in(2) ? std::string() : quote(in_.pick(kSeries)), ")"});
            case 2:
                return cat({ref("L"), ".",
                            in_.pick({"size", "sample_every", "refresh", "version", "series", "x"}),
                            " = ", value()});
            default:
                return cat({"local l = ", ref("L"),
                            " X[1] = { l.size, l.sample_every, l.refresh, l.version, l.series }"});
        }
    }

    std::string sensor_use() {
        switch (in_.below(7)) {
            case 0:
                return cat({x_slot(), " = ", ref("N"), ":read()"});
            case 1: {
                const std::string n = ref("N");
                const char* which = in_.pick({"on", "off"});
                std::string origin;
                if (in_.one_in(2)) {
                    origin = quote(in_.pick({"script", "console", "viewer", "file"}));
                }
                return cat({n, ":", which, "(", origin, ")"});
            }
            case 2:
                return cat({ref("N"), ".enabled = ", hostile() ? value() : "false"});
            case 3:
                return cat({x_slot(), " = ", ref("N"), ":channels()"});
            case 4:
                return cat({"local s = ", ref("N"),
                            " X[1] = { s.name, s.kind, s.joint, s.module, s.half, s.direction, "
                            "s.max_range, s.enabled, tostring(s) }"});
            case 5:
                return cat({ref("N"), " = ", ref("R"), ":sensor(", name(), ")"});
            default:
                return cat({x_slot(), " = ", ref("R"), ":sensors()"});
        }
    }

    // files written and read back; a robot that was saved must load again (else data is lost)
    std::string save_and_load() {
        const std::string p = path();
        switch (in_.below(7)) {
            case 0: {
                const std::string r = ref("R");
                const std::string slot_p = ref("P");
                return cat({"local p = ", r, ":save(", p, ") ", slot_p,
                            " = p if p then local r, e = gaitlab.robot.load(p) if not r then "
                            "__fuzz_finding('a saved robot does not load: ' .. tostring(e)) end ",
                            r, " = r end"});
            }
            case 1:
                return cat({ref("R"), " = gaitlab.robot.load(", p, ")"});
            case 2: {
                const std::string w = ref("W");
                const std::string slot_p = ref("P");
                return cat({"local p = ", w, ":save(", p, ") ", slot_p, " = p if p then ", w,
                            " = gaitlab.world.load(p) end"});
            }
            case 3:
                return cat({ref("W"), " = gaitlab.world.load(", p, ")"});
            case 4: {
                const std::string s = ref("S");
                std::string duration;
                if (in_.one_in(2)) duration = ", { duration = " + real(0, 1) + " }";
                const std::string slot_p = ref("P");
                return cat({"local p = ", s, ":save(", p, duration, ") ", slot_p,
                            " = p if p then local s, setup = gaitlab.simulation.load(p) ", s,
                            " = s T[1] = setup end"});
            }
            case 5:
                return cat({"local s, setup = gaitlab.simulation.load(", p, ") ", ref("S"),
                            " = s if type(setup) == 'table' then ", ref("W"),
                            " = setup.world end"});
            default: {
                const std::string r = ref("R");
                const std::string slot_p = ref("P");
                return cat({"local p = ", r, ":save_urdf(", p, ") ", slot_p, " = p if p then ", r,
                            " = gaitlab.robot.load_urdf(p) end"});
            }
        }
    }

    std::string robot_actuation() {
        switch (in_.below(5)) {
            case 0:
                return cat({ref("A"), " = ", ref("R"), ":actuation()"});
            case 1:
                return cat({x_slot(), " = ", ref("R"), ":actuate(", ref("A"), ")"});
            case 2:
                return cat({ref("P"), " = ", ref("A"), ":save(", path(), ")"});
            case 3:
                return cat({ref("A"), " = gaitlab.actuation.load(", path(), ")"});
            default:
                return cat(
                    {"local a = ", ref("A"), " ", x_slot(), " = { a:groups(), #a, tostring(a) }"});
        }
    }

    std::string run_data() {
        switch (in_.below(8)) {
            case 0:
                return cat({ref("D"), " = gaitlab.data.open(",
                            in_.one_in(2) ? ref("S") + ".record_dir" : path(), ")"});
            case 1:
                return cat({x_slot(), " = ", ref("D"), ":series()"});
            case 2:
                return cat({x_slot(), " = ", ref("D"), ":select(",
                            in_.one_in(2) ? series_list() : quote(in_.pick(kSeries)), ")"});
            case 3: {
                const std::string x = x_slot();
                const std::string d = ref("D");
                const std::string series = in_.one_in(2) ? quote(in_.pick(kSeries)) : name();
                std::string range;
                if (in_.one_in(2)) {
                    range = cat({", { from = ", real(0, 1), ", to = ", real(0, 1), " }"});
                }
                return cat({x, " = ", d, ":get(", series, range, ")"});
            }
            case 4:
                return cat(
                    {x_slot(), " = ", ref("D"), ":get(",
                     fields({"kind", "value", "joint", "source"},
                            [&](std::string_view k) {
                                if (k == "kind") {
                                    return quote(in_.pick({"robot", "controller", "sensor"}));
                                }
                                if (k == "joint") return integer(0, 9);
                                return name();
                            }),
                     ")"});
            case 5: {
                const std::string d = ref("D");
                return cat({x_slot(), " = { ", d, ":events(), ", d, ":log() }"});
            }
            case 6:
                return cat({"local d = ", ref("D"),
                            " X[1] = { d.dir, d.name, d.status, d.message, d.rows, d.truncated, "
                            "d.script, d.seed, d.started, d.dt, d.provenance, tostring(d) }"});
            default:
                return cat({x_slot(), " = ", ref("D"), "[", value(), "]"});
        }
    }

    std::string plot_or_export() {
        if (in_.one_in(2)) {
            return cat({x_slot(), " = ", ref("D"), ":export(",
                        fields({"series", "file", "dir", "from", "to"},
                               [&](std::string_view k) {
                                   if (k == "series") return series_list();
                                   if (k == "file" || k == "dir") return path();
                                   return real(0, 1);
                               }),
                        ")"});
        }
        return cat(
            {x_slot(), " = ", ref("D"), ":plot(",
             fields({"!series", "!output", "from", "to", "title", "width", "height"},
                    [&](std::string_view k) {
                        if (k == "series") return series_list();
                        if (k == "output") {
                            return in_.one_in(3) ? path() : quote(in_.pick({"p.png", "sub/p.png"}));
                        }
                        if (k == "title") return name();
                        if (k == "width" || k == "height") return integer(100, 400);
                        return real(0, 1);
                    }),
             ")"});
    }

    // what a script reads: measures, lists, fields, string forms and lengths of everything
    std::string query() {
        const std::string x = x_slot() + " = ";
        switch (in_.below(9)) {
            case 0:
                return cat({x, ref("R"), ":",
                            in_.pick({"position", "velocity", "displacement", "bodies", "joints",
                                      "sensors", "actuation"}),
                            "()"});
            case 1: {
                const std::string r = ref("R");
                return cat({x, "{ #", r, ", ", r, ".name, tostring(", r, ") }"});
            }
            case 2: {
                const std::string g = ref("G");
                return cat({x, g, ":joints() X[2] = #", g});
            }
            case 3: {
                const std::string c = ref("C");
                return cat({x, "{ ", c, ":params(), ", c, ":values(), ", c, ".name, ", c,
                            ".failed, ", c, ".error, tostring(", c, ") }"});
            }
            case 4:
                return cat({"local k = ", ref("K"),
                            " X[1] = { k.name, k.file, k.version, k.reload_error, "
                            "k.instruction_budget, tostring(k) }"});
            case 5:
                return cat({"local s = ", ref("S"),
                            " X[1] = { s.time, s.ticks, s.paused, s.dt, s.control_every, s.seed, "
                            "s.solver_iterations, s.on_controller_error, s.record_dir, "
                            "tostring(s), s:objects() }"});
            case 6:
                return cat({"local m = ", ref("M"),
                            " X[1] = { m.name, m.shape, m.length, m.width, m.height, m.radius, "
                            "m.mass, m.axis, m.range, m.max_speed, m.max_torque, m.kp, "
                            "m.friction, tostring(m) }"});
            case 7:
                return cat({x, "tostring(", ref("W"), ") .. tostring(", object(), ")"});
            default:
                return cat({"for k, v in pairs(gaitlab.modules) do X[1] = tostring(v) end X[2] = ",
                            object(), "[", value(), "]"});
        }
    }

    std::string templates() {
        switch (in_.below(3)) {
            case 0:
                return x_slot() + " = gaitlab.controller.templates()";
            case 1:
                return cat(
                    {ref("K"), " = gaitlab.controller.template(",
                     hostile() ? value() : quote(in_.pick({"sine", "cpg_chain", "blank", "none"})),
                     ")"});
            default:
                return cat({ref("P"), " = gaitlab.controller.write_template(",
                            quote(in_.pick({"sine", "cpg_chain", "blank", "nope"})), ", ", path(),
                            ")"});
        }
    }

    // a controller file written, then loaded (sandboxed or not), or reloaded
    std::string controller_from_file(int depth) {
        const std::string p = quote(in_.pick({"c1.lua", "c2.lua", "sub/c3.lua", "c1.lua"}));
        std::string s = cat({"local f = io.open(", p, ", 'w') if f then f:write(",
                             controller_file(depth), ") f:close() end "});
        if (in_.one_in(2)) {
            const std::string k = ref("K");
            std::string options;
            if (in_.one_in(3)) {
                options = cat({", { sandbox = ", in_.one_in(2) ? "false" : "true", " }"});
            }
            s += cat({k, " = gaitlab.controller.load(", p, options, ")"});
        } else {
            s += "gaitlab.controller.reload()";
        }
        return s;
    }

    // a method called on the wrong object, with odd arguments
    std::string wrong_self() {
        return cat({"local o = ", object(), " local f = type(o) == 'userdata' and o.",
                    in_.pick(kMethods), " if f then f(", object(), ", ", value(), ", ", value(),
                    ") end"});
    }

    Choices in_;
    unsigned hostility_ = 0;
    int nesting_ = 0;
    int in_step_ = 0;  // inside the step function of a controller class
};

}  // namespace

std::string generate_script(const std::uint8_t* data, std::size_t size) {
    return Generator(data, size).script();
}

Script script_for_input(const std::uint8_t* data, std::size_t size, bool strict_marks) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (text.substr(0, 2) == "--") {
        return {std::string(text), strict_marks && text.substr(0, 9) == "-- strict"};
    }
    return {generate_script(data, size), true};
}

}  // namespace gaitlab::fuzz
