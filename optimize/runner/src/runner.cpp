// The optimization runner: spec files, evaluations in a Lua state per worker, the results
// folder (see gaitlab/optimize/runner.h).
#include "gaitlab/optimize/runner.h"

#include <lua.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <mutex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fitness.h"
#include "gaitlab/error.h"
#include "gaitlab/optimize/backend.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/suggest.h"
#include "results.h"
#include "run_state.h"
#include "simulation_spec.h"

namespace gaitlab::optimize {

namespace {

namespace fs = std::filesystem;
using detail::fitness_json;
using detail::parameters_json;
using scripting::LuaHost;

// settle and duration, s each: a million simulated seconds (11 days) is more than any
// evaluation runs, and within what a simulation can run at any dt (>= 1e-6 s)
constexpr double kMaxEvaluationSeconds = 1e6;

const std::vector<std::string> kFields = {
    "parameters", "build",       "fitness", "duration", "settle",     "robot", "method",
    "population", "generations", "worlds",  "seeds",    "simulation", "set"};

// the measuring part of an evaluation: fitness.cpp
const char* const kMeasure = detail::measure_chunk();

std::string lua_type_name(lua_State* L, int index) {
    return luaL_typename(L, index);
}

// a number as messages show it: "nan" whatever its sign bit (0/0 in Lua is printed "-nan")
std::string shown(double v) {
    return std::isnan(v) ? "nan" : fmt::format("{}", v);
}

// "FILE: FIELD: WHAT"
[[noreturn]] void bad(const std::string& file, const std::string& field, const std::string& what) {
    throw SpecError(fmt::format("{}: {}: {}", file, field, what));
}

// a LuaHost that evaluates: records nothing, prints nothing, reports nothing
std::unique_ptr<LuaHost> make_host(const std::string& file) {
    auto host = std::make_unique<LuaHost>();
    scripting::RecordSettings rec;
    rec.disabled = true;
    host->set_recording(rec);
    host->set_print(false);
    host->set_reporter([](const std::string&) {});
    host->set_args(file, {});
    host->seed(0);
    // os.exit in a spec ended gaitlab optimize at once and silently: here it is an error, so
    // the evaluation that called it fails (named, with its line) and the run goes on
    lua_State* L = host->state();
    lua_getglobal(L, "os");
    if (lua_istable(L, -1)) {
        lua_pushcfunction(L, [](lua_State* S) -> int {
            return luaL_error(S,
                              "os.exit ends no evaluation: return from build or the fitness "
                              "function (an error fails the evaluation; the run goes on)");
        });
        lua_setfield(L, -2, "exit");
    }
    lua_pop(L, 1);
    return host;
}

// runs the spec file in `host`; leaves what it returned (a table) on the stack
void load_spec_table(LuaHost& host, const std::string& file) {
    lua_State* L = host.state();
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) {
        throw SpecError(fmt::format("{}: {}", file,
                                    fs::exists(file, ec) ? "not a regular file"
                                                         : "no such file (an optimization spec, "
                                                           "FILE.lua, expected)"));
    }
    if (luaL_loadfilex(L, file.c_str(), "t") != LUA_OK) {
        std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "cannot load";
        lua_pop(L, 1);
        throw SpecError(message);
    }
    scripting::protected_call(L, 0, 1);
    if (!lua_istable(L, -1)) {
        const std::string got = lua_type_name(L, -1);
        lua_pop(L, 1);
        throw SpecError(fmt::format(
            "{}: the spec file must return a table {{ parameters =, build =, fitness =, "
            "duration = ... }} (got {})",
            file, got));
    }
    // simulation = "FILE.xml": its build function
    detail::install_simulation_build(host, file);
}

double number_field(lua_State* L, const std::string& file, const char* field, double fallback,
                    bool required, const char* expected) {
    lua_getfield(L, -1, field);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        if (required) bad(file, field, fmt::format("missing ({} expected)", expected));
        return fallback;
    }
    if (!lua_isnumber(L, -1) || lua_type(L, -1) != LUA_TNUMBER) {
        const std::string got = lua_type_name(L, -1);
        lua_pop(L, 1);
        bad(file, field, fmt::format("{} expected, got {}", expected, got));
    }
    const double v = lua_tonumber(L, -1);
    lua_pop(L, 1);
    if (!std::isfinite(v)) bad(file, field, fmt::format("{} expected, got {}", expected, shown(v)));
    return v;
}

int count_field(lua_State* L, const std::string& file, const char* field, int fallback) {
    lua_getfield(L, -1, field);
    const bool absent = lua_isnil(L, -1);
    lua_pop(L, 1);
    if (absent) return fallback;
    const double v = number_field(L, file, field, fallback, false, "a whole number >= 1");
    if (v < 1 || v != std::floor(v) || v > 1e9) {
        bad(file, field, fmt::format("a whole number >= 1 expected, got {}", shown(v)));
    }
    return static_cast<int>(v);
}

std::string method_name(const std::string& m, const std::string& where) {
    if (m == "ga" || m == "cmaes" || m == "pgpe") return m;
    throw SpecError(
        fmt::format("{}: unknown method '{}'{} (expected \"ga\", \"cmaes\" or \"pgpe\")", where, m,
                    did_you_mean(m, {"ga", "cmaes", "pgpe"})));
}

// reads the parameters table on top of the stack
void read_parameters(lua_State* L, Spec& spec) {
    const std::string& file = spec.file;
    if (!lua_istable(L, -1)) {
        bad(file, "parameters",
            fmt::format("a table {{ NAME = {{MIN, MAX}}, ... }} expected, got {}",
                        lua_type_name(L, -1)));
    }
    struct Entry {
        Parameter p;
        bool has_initial = false;
        double initial = 0;
    };
    std::vector<Entry> entries;
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
        if (lua_type(L, -2) != LUA_TSTRING) {
            bad(file, "parameters",
                "names expected as keys ({ amplitude = {10, 60}, ... }), got a " +
                    lua_type_name(L, -2) + " key");
        }
        Entry e;
        e.p.name = lua_tostring(L, -2);
        const std::string field = "parameters." + e.p.name;
        if (!lua_istable(L, -1)) {
            bad(file, field,
                fmt::format("a range {{MIN, MAX}} expected (optionally integer = true, initial "
                            "= VALUE), got {}",
                            lua_type_name(L, -1)));
        }
        // the keys of one parameter
        lua_pushnil(L);
        while (lua_next(L, -2) != 0) {
            const bool index = lua_type(L, -2) == LUA_TNUMBER && lua_isinteger(L, -2) &&
                               (lua_tointeger(L, -2) == 1 || lua_tointeger(L, -2) == 2);
            const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "";
            if (!index && key != "integer" && key != "initial") {
                bad(file, field,
                    fmt::format("unknown key '{}' (expected {{MIN, MAX}}, integer = true, "
                                "initial = VALUE)",
                                key.empty() ? luaL_tolstring(L, -2, nullptr) : key));
            }
            lua_pop(L, 1);
        }
        for (int i = 1; i <= 2; ++i) {
            lua_rawgeti(L, -1, i);
            if (lua_type(L, -1) != LUA_TNUMBER) {
                bad(file, field,
                    fmt::format("{} of the range {{MIN, MAX}}: a number expected, got {}",
                                i == 1 ? "MIN" : "MAX", lua_type_name(L, -1)));
            }
            (i == 1 ? e.p.min : e.p.max) = lua_tonumber(L, -1);
            lua_pop(L, 1);
        }
        lua_getfield(L, -1, "integer");
        if (!lua_isnil(L, -1) && !lua_isboolean(L, -1)) {
            bad(file, field + ".integer", "true or false expected, got " + lua_type_name(L, -1));
        }
        e.p.integer = lua_toboolean(L, -1) != 0;
        lua_pop(L, 1);
        lua_getfield(L, -1, "initial");
        if (!lua_isnil(L, -1)) {
            if (lua_type(L, -1) != LUA_TNUMBER) {
                bad(file, field + ".initial", "a number expected, got " + lua_type_name(L, -1));
            }
            e.has_initial = true;
            e.initial = lua_tonumber(L, -1);
        }
        lua_pop(L, 1);
        entries.push_back(e);
        lua_pop(L, 1);
    }
    if (entries.empty()) {
        bad(file, "parameters", "at least one parameter expected ({ amplitude = {10, 60} })");
    }
    // table order is not defined in Lua: sorted by name, the order is the same every time
    std::sort(entries.begin(), entries.end(),
              [](const Entry& a, const Entry& b) { return a.p.name < b.p.name; });
    for (const Entry& e : entries)
        spec.parameters.push_back(e.p);
    try {
        validate_parameters(spec.parameters);
    } catch (const Error& error) {
        throw SpecError(fmt::format("{}: parameters: {}", file, error.what()));
    }
    const bool any_initial =
        std::any_of(entries.begin(), entries.end(), [](const Entry& e) { return e.has_initial; });
    if (any_initial) {
        for (const Entry& e : entries) {
            const double v = e.has_initial ? e.initial : (e.p.min + e.p.max) / 2;
            if (!(v >= e.p.min && v <= e.p.max)) {
                bad(file, "parameters." + e.p.name + ".initial",
                    fmt::format("{} is outside the range [{}, {}]", shown(v), e.p.min, e.p.max));
            }
            spec.initial.push_back(v);
        }
    }
}

// reads the spec table on top of L's stack
Spec read_spec(lua_State* L, const std::string& file) {
    Spec spec;
    spec.file = file;
    // unknown fields first: a misspelt one would otherwise read as missing
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
        const std::string key = lua_type(L, -2) == LUA_TSTRING ? lua_tostring(L, -2) : "";
        if (std::find(kFields.begin(), kFields.end(), key) == kFields.end()) {
            const std::string shown = key.empty() ? luaL_tolstring(L, -2, nullptr) : key;
            throw SpecError(fmt::format(
                "{}: unknown field '{}'{} (expected parameters, build, fitness, duration, settle, "
                "robot, method, population, generations, worlds, seeds, simulation, set)",
                file, shown, did_you_mean(shown, kFields)));
        }
        lua_pop(L, 1);
    }
    lua_getfield(L, -1, "parameters");
    if (lua_isnil(L, -1))
        bad(file, "parameters", "missing (a table { NAME = {MIN, MAX}, ... } expected)");
    read_parameters(L, spec);
    lua_pop(L, 1);

    lua_getfield(L, -1, "build");
    if (!lua_isfunction(L, -1)) {
        bad(file, "build",
            lua_isnil(L, -1)
                ? std::string("missing (a function(p) that returns a simulation "
                              "expected)")
                : "a function(p) that returns a simulation expected, got " + lua_type_name(L, -1));
    }
    lua_pop(L, 1);

    lua_getfield(L, -1, "fitness");
    detail::read_fitness(L, spec);
    lua_pop(L, 1);

    detail::read_cases(L, spec);
    // an evaluation runs settle + duration simulated seconds: beyond kMaxEvaluationSeconds no
    // simulation could run them (every evaluation failed instead of the spec being refused)
    spec.duration = number_field(L, file, "duration", 0, true, "a number of seconds > 0");
    if (!(spec.duration > 0 && spec.duration <= kMaxEvaluationSeconds)) {
        bad(file, "duration",
            fmt::format("a number of seconds in (0, 1e6] expected, got {}", spec.duration));
    }
    spec.settle = number_field(L, file, "settle", 0, false, "a number of seconds >= 0");
    if (!(spec.settle >= 0 && spec.settle <= kMaxEvaluationSeconds)) {
        bad(file, "settle",
            fmt::format("a number of seconds in [0, 1e6] expected, got {}", spec.settle));
    }

    lua_getfield(L, -1, "robot");
    if (!lua_isnil(L, -1)) {
        if (lua_type(L, -1) != LUA_TSTRING)
            bad(file, "robot", "a robot's name expected, got " + lua_type_name(L, -1));
        spec.robot = lua_tostring(L, -1);
    }
    lua_pop(L, 1);

    lua_getfield(L, -1, "method");
    if (!lua_isnil(L, -1)) {
        if (lua_type(L, -1) != LUA_TSTRING) {
            bad(file, "method",
                "\"ga\", \"cmaes\" or \"pgpe\" expected, got " + lua_type_name(L, -1));
        }
        spec.method = method_name(lua_tostring(L, -1), file + ": method");
    }
    lua_pop(L, 1);
    spec.population = count_field(L, file, "population", 0);
    spec.generations = count_field(L, file, "generations", spec.generations);
    return spec;
}

// the parameters as a Lua table name -> value (integers as Lua integers)
void push_parameters(lua_State* L, const Spec& spec, const std::vector<double>& x) {
    lua_createtable(L, 0, static_cast<int>(x.size()));
    for (size_t i = 0; i < x.size(); ++i) {
        if (spec.parameters[i].integer) {
            lua_pushinteger(L, static_cast<lua_Integer>(x[i]));
        } else {
            lua_pushnumber(L, x[i]);
        }
        lua_setfield(L, -2, spec.parameters[i].name.c_str());
    }
}

// what an evaluation leaves on the Lua stack (its simulation, garbage) goes when it ends, before
// the next one
class Clean {
  public:
    explicit Clean(lua_State* L) : L_(L), top_(lua_gettop(L)) {}
    Clean(const Clean&) = delete;
    Clean& operator=(const Clean&) = delete;
    ~Clean() {
        lua_settop(L_, top_);
        lua_gc(L_, LUA_GCCOLLECT);
    }

  private:
    lua_State* L_;
    int top_;
};

}  // namespace

Spec load_spec(const std::string& path) {
    std::unique_ptr<LuaHost> host = make_host(path);
    load_spec_table(*host, path);
    Spec spec = read_spec(host->state(), path);
    lua_pop(host->state(), 1);
    return spec;
}

Evaluator::Evaluator(const Spec& spec, std::uint64_t seed)
    : spec_(spec), host_(make_host(spec.file)), seed_(seed) {
    lua_State* L = host_->state();
    load_spec_table(*host_, spec.file);
    spec_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    if (luaL_loadbufferx(L, kMeasure, std::strlen(kMeasure), "=(gaitlab optimize)", "t") !=
        LUA_OK) {
        const std::string message = lua_tostring(L, -1);
        lua_pop(L, 1);
        throw Error("optimize: " + message);
    }
    measure_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
}

Evaluator::~Evaluator() = default;

void Evaluator::interrupt(int signal) {
    host_->interrupt(signal);
}

double Evaluator::evaluate(const std::vector<double>& x) {
    // math.random's seed: the spec's seeds, or this evaluator's (a sweep's --seed; 0)
    if (spec_.worlds == 0 && spec_.seeds.empty()) return evaluate_case(x, 0, seed_);
    // several worlds or seeds: the mean of the runs; one that fails fails the individual
    const std::vector<std::uint64_t> seeds =
        spec_.seeds.empty() ? std::vector<std::uint64_t>{seed_} : spec_.seeds;
    double sum = 0;
    for (int w = spec_.worlds > 0 ? 1 : 0; w <= spec_.worlds; ++w) {
        for (const std::uint64_t seed : seeds) {
            try {
                sum += evaluate_case(x, w, seed);
            } catch (const Error& e) {
                std::string where = w > 0 ? fmt::format("world {}", w) : "";
                if (!spec_.seeds.empty())
                    where += fmt::format("{}seed {}", where.empty() ? "" : ", ", seed);
                throw Error(fmt::format("{} ({})", e.what(), where));
            }
        }
    }
    return sum /
           (static_cast<double>(std::max(spec_.worlds, 1)) * static_cast<double>(seeds.size()));
}

double Evaluator::evaluate_case(const std::vector<double>& x, int world, std::uint64_t seed) {
    lua_State* L = host_->state();
    const Clean clean(L);
    host_->seed(seed);
    try {
        // build(p, world, seed)
        lua_rawgeti(L, LUA_REGISTRYINDEX, spec_ref_);
        const int spec_index = lua_gettop(L);
        lua_getfield(L, spec_index, "build");
        push_parameters(L, spec_, x);
        lua_getfield(L, spec_index, "worlds");
        if (world > 0 && lua_istable(L, -1)) {
            lua_rawgeti(L, -1, world);
            lua_remove(L, -2);
        } else {
            lua_pop(L, 1);
            lua_pushnil(L);
        }
        lua_pushinteger(L, static_cast<lua_Integer>(seed));
        scripting::protected_call(L, 3, 1);
        if (!luaL_testudata(L, -1, "gaitlab.Simulation")) {
            throw Error(
                fmt::format("build: a simulation expected as its result, got {} (return "
                            "gaitlab.simulation{{ ... }})",
                            lua_type_name(L, -1)));
        }
        const int sim_index = lua_gettop(L);
        lua_rawgeti(L, LUA_REGISTRYINDEX, measure_ref_);
        lua_pushvalue(L, sim_index);
        lua_pushnumber(L, spec_.settle);
        lua_pushnumber(L, spec_.duration);
        lua_pushstring(L, spec_.fitness.c_str());
        lua_pushstring(L, spec_.robot.c_str());
        lua_getfield(L, spec_index, "fitness");
        push_parameters(L, spec_, x);
        lua_pushnumber(L, spec_.direction.empty() ? 0.0 : spec_.direction[0]);
        lua_pushnumber(L, spec_.direction.empty() ? 0.0 : spec_.direction[1]);
        scripting::protected_call(L, 9, 1);
        if (lua_type(L, -1) != LUA_TNUMBER) {
            throw Error(fmt::format("fitness: a number expected as its result, got {}",
                                    lua_type_name(L, -1)));
        }
        const double f = lua_tonumber(L, -1);
        if (!std::isfinite(f)) {
            throw Error(fmt::format("fitness: a finite number expected as its result, got {}",
                                    std::isnan(f) ? "nan"
                                    : f > 0       ? "inf"
                                                  : "-inf"));
        }
        return f;
    } catch (const scripting::ScriptError& e) {
        // Lua shortens long file names in its messages ("...ng/spec.lua:11: x"): the whole
        // name and line the error carries, then what Lua said after its position
        std::string message = e.what();
        if (!e.file().empty() && e.line() > 0) {
            const std::string at = fmt::format(":{}: ", e.line());
            const auto pos = message.find(at);
            if (pos != std::string::npos) message = message.substr(pos + at.size());
            // the runner's own measuring code: the spec is what is wrong
            if (e.file() == "(gaitlab optimize)") throw Error(spec_.file + ": " + message);
            throw Error(fmt::format("{}:{}: {}", e.file(), e.line(), message));
        }
        if (message.rfind(spec_.file, 0) == 0) throw;
        throw Error(fmt::format("{}: {}", spec_.file, message));
    } catch (const Error& e) {
        const std::string message = e.what();
        // a message that names the spec file already says where
        if (message.rfind(spec_.file, 0) == 0) throw;
        throw Error(fmt::format("{}: {}", spec_.file, message));
    }
}

void Evaluator::save(const std::vector<double>& x, const std::string& path) {
    lua_State* L = host_->state();
    const Clean clean(L);
    // several worlds or seeds: the first of each
    const std::uint64_t seed = spec_.seeds.empty() ? seed_ : spec_.seeds[0];
    host_->seed(seed);
    lua_rawgeti(L, LUA_REGISTRYINDEX, spec_ref_);
    lua_getfield(L, -1, "build");
    push_parameters(L, spec_, x);
    lua_getfield(L, -3, "worlds");
    if (lua_istable(L, -1)) {
        lua_rawgeti(L, -1, 1);
        lua_remove(L, -2);
    }
    lua_pushinteger(L, static_cast<lua_Integer>(seed));
    try {
        scripting::protected_call(L, 3, 1);
    } catch (const Error& e) {
        throw Error(fmt::format("{}: build: {}", spec_.file, e.what()));
    }
    if (!luaL_testudata(L, -1, "gaitlab.Simulation")) {
        throw Error(fmt::format("{}: build: a simulation expected as its result, got {}",
                                spec_.file, lua_type_name(L, -1)));
    }
    const int sim = lua_gettop(L);
    lua_getfield(L, sim, "save");
    lua_pushvalue(L, sim);
    lua_pushstring(L, path.c_str());
    lua_createtable(L, 0, 1);
    lua_pushnumber(L, spec_.settle + spec_.duration);
    lua_setfield(L, -2, "duration");
    scripting::protected_call(L, 3, 2);
    if (lua_isnil(L, -2)) {
        throw IoError(lua_isstring(L, -1) ? lua_tostring(L, -1)
                                          : fmt::format("cannot write {}", path));
    }
}

RunResult run_optimization(const Spec& spec, const RunOptions& options,
                           const std::function<void(const Progress&)>& on_generation,
                           const std::atomic<int>* stop,
                           const std::function<void(const Tick&)>& on_evaluation) {
    RunResult result;
    result.method = options.method.empty() ? spec.method : method_name(options.method, "--method");
    result.generations = options.generations > 0 ? options.generations : spec.generations;
    result.population = options.population > 0 ? options.population : spec.population;
    if (options.workers < 1) {
        throw SpecError(
            fmt::format("--workers: a whole number >= 1 expected, got {}", options.workers));
    }
    std::unique_ptr<Method> method;
    if (result.method == "ga") {
        GaOptions o;
        if (result.population > 0) o.population = result.population;
        o.initial = spec.initial;
        method = make_ga(spec.parameters, o, options.seed);
        result.population = o.population;
    } else if (result.method == "cmaes") {
        CmaesOptions o;
        o.population = result.population;
        o.initial = spec.initial;
        method = make_cmaes(spec.parameters, o, options.seed);
    } else {
        PgpeOptions o;
        if (result.population > 0) o.population = result.population;
        o.initial = spec.initial;
        method = make_pgpe(spec.parameters, o, options.seed);
        result.population = o.population;
    }

    // the run's state, written after each generation: what --resume goes on from
    const fs::path out(options.out);
    detail::RunState state;
    state.spec_file = spec.file;
    state.spec_text = detail::read_text_file(spec.file);
    state.method = result.method;
    state.population = result.population;
    state.generations = result.generations;
    state.seed = options.seed;
    state.command = options.command;
    if (options.resume) {
        const detail::RunState saved = detail::read_run_state(out);
        detail::check_resumable(saved, state, out);
        method = load_method(saved.method_state, (out / "state.json").string());
        state = saved;
    }

    // the results folder: new, or empty (never overwrite an earlier run's results)
    std::error_code ec;
    if (options.resume) {
        // what was written after the last state (a generation cut short) goes: it is evaluated
        // again, the same way
        const fs::path path = out / "evaluations.jsonl";
        const auto size = fs::file_size(path, ec);
        if (ec || size < state.jsonl_bytes) {
            throw SpecError(fmt::format(
                "--resume: {}: {} (the run's state says {} bytes were written): not resumed",
                path.string(), ec ? "cannot read it" : fmt::format("only {} bytes", size),
                state.jsonl_bytes));
        }
        fs::resize_file(path, state.jsonl_bytes, ec);
        if (ec) throw IoError(fmt::format("{}: cannot truncate: {}", path.string(), ec.message()));
    } else {
        detail::open_results_folder(options.out);
    }
    fs::create_directories(out, ec);
    if (ec)
        throw IoError(fmt::format("{}: cannot create the folder: {}", options.out, ec.message()));
    const fs::path jsonl_path = out / "evaluations.jsonl";
    std::ofstream jsonl(jsonl_path,
                        std::ios::binary | (options.resume ? std::ios::app : std::ios::trunc));
    if (!jsonl) {
        throw IoError(
            fmt::format("{}: cannot create{}", jsonl_path.string(), detail::reason(errno)));
    }
    state.method_state = method->save();
    if (!options.resume) detail::write_run_state(out, state);

    // the given backend (MPI ranks), or one Lua state per worker thread here
    EvaluationPool pool(spec, options.workers, 0, stop, options.backend);

    // wall time counts the earlier sessions of a resumed run
    const auto started = std::chrono::steady_clock::now() -
                         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(state.wall));
    std::mutex tick_mutex;
    Tick tick;
    tick.generations = result.generations;
    tick.mean = std::numeric_limits<double>::quiet_NaN();
    // after each evaluation (one call at a time)
    const EvaluationDone evaluated = [&](std::size_t, const Evaluation&) {
        if (!on_evaluation) return;
        std::lock_guard<std::mutex> lock(tick_mutex);
        ++tick.done;
        ++tick.evaluations;
        tick.wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        on_evaluation(tick);
    };
    std::size_t first_population = static_cast<std::size_t>(state.first_population);
    for (int g = method->generation(); g < result.generations; ++g) {
        const std::vector<std::vector<double>> xs = method->ask();
        if (g == 0) first_population = xs.size();
        {
            std::lock_guard<std::mutex> lock(tick_mutex);
            tick.generation = g;
            tick.done = 0;
            tick.individuals = static_cast<int>(xs.size());
            tick.best = method->best_fitness();
        }
        const std::vector<Evaluation> ev = pool.evaluate(xs, evaluated);
        if (stop && stop->load() != 0) {
            throw Error(fmt::format("interrupted after {} generations", g));
        }
        std::vector<double> fitness(ev.size());
        Progress p;
        p.generation = g;
        p.generations = result.generations;
        p.individuals = static_cast<int>(ev.size());
        int ok = 0;
        std::string lines;
        for (size_t i = 0; i < ev.size(); ++i) {
            fitness[i] = ev[i].failed() ? std::numeric_limits<double>::quiet_NaN() : ev[i].fitness;
            if (ev[i].failed()) {
                ++p.failed;
                if (p.first_error.empty()) p.first_error = ev[i].error;
            } else {
                ++ok;
            }
            lines += detail::evaluation_line(spec, g, i, xs[i], ev[i]);
        }
        detail::append_text(jsonl, jsonl_path, lines);
        method->tell(fitness);
        p.best = method->best_fitness();
        // each value divided before they are added: fitness values near the largest double
        // (1e308) made the sum, and the mean, infinite
        p.mean = ok > 0 ? 0 : std::numeric_limits<double>::quiet_NaN();
        for (size_t i = 0; i < ev.size(); ++i)
            if (!ev[i].failed()) p.mean += fitness[i] / ok;
        p.evaluations = method->evaluations();
        p.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        state.first_population = static_cast<int>(first_population);
        state.generation = method->generation();
        state.jsonl_bytes += lines.size();
        state.wall = p.wall;
        state.method_state = method->save();
        detail::write_run_state(out, state);
        {
            std::lock_guard<std::mutex> lock(tick_mutex);
            tick.mean = p.mean;
        }
        if (on_generation) on_generation(p);
    }
    result.best = method->best();
    result.best_fitness = method->best_fitness();
    result.evaluations = method->evaluations();

    // the convergence plot (gnuplot, a process of its own) is drawn while the best individual
    // is saved and recorded: the run's serial tail is the longer of the two, not their sum
    std::future<std::string> plot = std::async(std::launch::async, [&] {
        return detail::plot_convergence(out,
                                        fmt::format("{}: {} ({}, seed {})", spec.file, spec.fitness,
                                                    result.method, options.seed),
                                        spec.fitness);
    });
    // the best individual as a simulation file that gaitlab run runs (and its parts: the
    // actuation file holds the controllers' parameters)
    if (!result.best.empty()) {
        const fs::path path = fs::absolute(out / "best" / "best.xml");
        try {
            Evaluator(spec).save(result.best, path.string());
            result.simulation = (out / "best" / "best.xml").string();
        } catch (const Error& e) {
            result.simulation_error = e.what();
        }
    }
    // ... recorded, a run folder that gaitlab data and gaitlab view show
    if (!result.simulation.empty()) {
        result.run_error = detail::record_run(fs::absolute(result.simulation).string(), out / "run",
                                              state.command);
        if (result.run_error.empty()) result.run = (out / "run").string();
    }
    result.plot_error = plot.get();
    if (result.plot_error.empty()) result.plot = (out / "convergence.png").string();

    nlohmann::ordered_json best;
    best["format"] = "gaitlab-optimize-best";
    best["version"] = 1;
    best["spec"] = spec.file;
    best["method"] = result.method;
    best["seed"] = options.seed;
    best["generations"] = result.generations;
    best["population"] = first_population;
    best["evaluations"] = result.evaluations;
    best["fitness_kind"] = spec.fitness;
    best["fitness"] = fitness_json(result.best_fitness);
    best["parameters"] =
        result.best.empty() ? nlohmann::ordered_json(nullptr) : parameters_json(spec, result.best);
    if (!result.simulation.empty()) best["simulation"] = "best/best.xml";
    if (!result.simulation_error.empty()) best["simulation_error"] = result.simulation_error;
    if (!result.run.empty()) best["run"] = "run";
    if (!result.run_error.empty()) best["run_error"] = result.run_error;
    if (!result.plot.empty()) best["plot"] = "convergence.png";
    if (!result.plot_error.empty()) best["plot_error"] = result.plot_error;
    best["command"] = state.command;  // the one that began the run
    try {
        detail::write_file((out / "best.json").string(), detail::json_text(best, 2) + "\n");
    } catch (const IoError& e) {
        // a disk that fills up usually stopped the best's run first: best.json would have
        // said so (run_error), and cannot, so the message does
        if (result.run_error.empty()) throw;
        throw IoError(fmt::format("{} (the best's run could not be recorded either: {})", e.what(),
                                  result.run_error));
    }
    return result;
}

}  // namespace gaitlab::optimize
