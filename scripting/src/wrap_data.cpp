// gaitlab.data: reading run folders (gaitlab.data.open), exporting and plotting their series,
// and live buffers of a running simulation (sim:live{...}).
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/live.h"
#include "gaitlab/plot.h"
#include "gaitlab/run_data.h"
#include "lua_util.h"
#include "recording.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

namespace fs = std::filesystem;
using RunPtr = std::shared_ptr<RunData>;

// live buffers and the simulation they watch (kept alive as long as the buffers)
struct LiveHandle {
    std::shared_ptr<Simulation> sim;
    std::shared_ptr<LiveBuffers> buffers;
};

RunData& check_run(lua_State* L, int index) {
    return *check_object<RunPtr>(L, index, kRunType);
}

LiveBuffers& check_live(lua_State* L, int index) {
    return *check_object<LiveHandle>(L, index, kLiveType).buffers;
}

void push_numbers(lua_State* L, const std::vector<double>& v) {
    lua_createtable(L, static_cast<int>(v.size()), 0);
    for (size_t i = 0; i < v.size(); ++i) {
        lua_pushnumber(L, v[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
}

void push_strings(lua_State* L, const std::vector<std::string>& v) {
    lua_createtable(L, static_cast<int>(v.size()), 0);
    for (size_t i = 0; i < v.size(); ++i) {
        lua_pushstring(L, v[i].c_str());
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
    }
}

void set_string(lua_State* L, const char* key, const std::string& v) {
    lua_pushstring(L, v.c_str());
    lua_setfield(L, -2, key);
}

// { name, kind, source, value, joint, body, unit } (joint and body only when there is one)
void push_info(lua_State* L, const SeriesInfo& s) {
    lua_createtable(L, 0, 7);
    set_string(L, "name", s.name);
    set_string(L, "kind", to_string(s.kind));
    set_string(L, "source", s.source);
    set_string(L, "value", s.value);
    if (s.joint > 0) {
        lua_pushinteger(L, s.joint);
        lua_setfield(L, -2, "joint");
    }
    if (!s.body.empty()) set_string(L, "body", s.body);
    set_string(L, "unit", s.unit);
}

// a list of names or patterns: a string or a list of strings
std::vector<std::string> to_names(lua_State* L, int index, int arg, const std::string& what) {
    std::vector<std::string> names;
    if (lua_type(L, index) == LUA_TSTRING) {
        names.emplace_back(to_string(L, index));
        return names;
    }
    if (!lua_istable(L, index)) {
        throw ArgError(
            arg, what + "a series name or a list of names expected, got " + type_name(L, index));
    }
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, index, i);
        if (lua_type(L, -1) != LUA_TSTRING) {
            const std::string t = type_name(L, -1);
            lua_pop(L, 1);
            throw ArgError(arg, what + "list of series names expected, got a " + t + " in it");
        }
        names.emplace_back(to_string(L, -1));
        lua_pop(L, 1);
    }
    if (names.empty()) throw ArgError(arg, what + "at least one series name expected");
    return names;
}

// { from = , to = } at `index` (optional)
void to_range(lua_State* L, int index, int arg, double& from, double& to) {
    from = -RunData::kInf;
    to = RunData::kInf;
    if (lua_isnoneornil(L, index)) return;
    Fields f(L, index, arg, {"from", "to"});
    from = f.number("from", from);
    to = f.number("to", to);
}

// gaitlab.data.open(dir): a gaitlab.Run, or nil and a message
int data_open(lua_State* L) {
    return protect(L, [&] {
        const std::string dir = check_string(L, 1);
        refuse_zero_byte(dir);
        std::shared_ptr<RunData> run;
        std::string failed;
        try {
            run = std::make_shared<RunData>(dir);
        } catch (const IoError& e) {
            failed = e.what();
        } catch (const FormatError& e) {
            failed = e.what();
        }
        if (!run) return push_fail(L, failed);
        new_object<RunPtr>(L, kRunType, std::move(run));
        return 1;
    });
}

int run_series(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        const auto& series = run.series();
        lua_createtable(L, static_cast<int>(series.size()), 0);
        for (size_t i = 0; i < series.size(); ++i) {
            push_info(L, series[i]);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

// run:select(pattern or {patterns}): the matching names, in file order
int run_select(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        const std::vector<std::string> patterns = to_names(L, 2, 2, "");
        try {
            push_strings(L, run.select(patterns));
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        return 1;
    });
}

// run:get(name | { kind =, value =, joint =, source = } [, { from =, to = }])
int run_get(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        double from = 0, to = 0;
        to_range(L, 3, 3, from, to);
        std::string name;
        try {
            if (lua_type(L, 2) == LUA_TSTRING) {
                name = to_string(L, 2);
                run.find(name);
            } else if (lua_istable(L, 2)) {
                Fields f(L, 2, 2, {"kind", "value", "joint", "source"});
                const std::string k = f.string("kind", "");
                SeriesKind kind;
                if (!parse_series_kind(k, kind)) {
                    f.fail("kind",
                           "'robot', 'controller', 'sensor' or 'object' expected, got '" + k + "'");
                }
                if (!f.has("value")) f.fail("value", "string expected, got nil");
                const long long joint = f.integer("joint", 0);
                name = run.find(kind, f.string("value", ""), static_cast<int>(joint),
                                f.string("source", ""))
                           .name;
            } else {
                throw ArgError(2, "series name or {kind =, value =, joint =} expected, got " +
                                      type_name(L, 2));
            }
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        const SeriesData d = run.get(name, from, to);
        push_info(L, d.info);
        push_numbers(L, d.time);
        lua_setfield(L, -2, "time");
        push_numbers(L, d.values);
        lua_setfield(L, -2, "values");
        return 1;
    });
}

int run_events(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        const std::vector<Event> events = run.events();
        const double dt = run.meta().options.dt;
        lua_createtable(L, static_cast<int>(events.size()), 0);
        for (size_t i = 0; i < events.size(); ++i) {
            const Event& e = events[i];
            lua_createtable(L, 0, 7);
            lua_pushinteger(L, e.tick);
            lua_setfield(L, -2, "tick");
            lua_pushnumber(L, static_cast<double>(e.tick) * dt);
            lua_setfield(L, -2, "time");
            set_string(L, "origin", to_string(e.origin));
            set_string(L, "kind", to_string(e.kind));
            set_string(L, "name", e.name);
            lua_pushnumber(L, e.value);
            lua_setfield(L, -2, "value");
            if (!e.detail.empty()) set_string(L, "detail", e.detail);
            lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
        }
        return 1;
    });
}

int run_log(lua_State* L) {
    return protect(L, [&] {
        lua_pushstring(L, check_run(L, 1).log().c_str());
        return 1;
    });
}

// run:export{ series = , file = | dir = , from = , to = }: one CSV with every series, or one
// file per series in a folder; returns the list of files written
int run_export(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        Fields f(L, 2, 2, {"series", "file", "dir", "from", "to"});
        f.push("series");
        const std::vector<std::string> patterns = to_names(L, -1, 2, "field 'series': ");
        lua_pop(L, 1);
        const double from = f.number("from", -RunData::kInf), to = f.number("to", RunData::kInf);
        if (f.has("file") == f.has("dir")) f.fail("file", "give either file = or dir =");
        std::vector<std::string> names;
        try {
            names = run.select(patterns);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        std::vector<std::string> written;
        if (f.has("file")) {
            const std::string file = f.string("file", "");
            run.write_csv(file, names, from, to);
            written.push_back(file);
        } else {
            written = run.write_split(f.string("dir", ""), names, from, to);
        }
        push_strings(L, written);
        return 1;
    });
}

// run:plot{ series = , output = , from = , to = , title = , width = , height = }: writes the
// PNG through gnuplot; returns the PNG, the gnuplot script and its data
int run_plot(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        Fields f(L, 2, 2, {"series", "x", "y", "output", "from", "to", "title", "width", "height"});
        PlotOptions o;
        // a path plot (x and y) or series against time
        o.x = f.string("x", "");
        o.y = f.string("y", "");
        if ((o.x.empty() && o.y.empty()) || f.has("series")) {
            f.push("series");
            o.series = to_names(L, -1, 2, "field 'series': ");
            lua_pop(L, 1);
        }
        if (!f.has("output")) f.fail("output", "file name of the PNG expected, got nil");
        o.output = f.string("output", "");
        o.from = f.number("from", o.from);
        o.to = f.number("to", o.to);
        o.title = f.string("title", "");
        o.width = static_cast<int>(f.integer("width", o.width));
        o.height = static_cast<int>(f.integer("height", o.height));
        PlotFiles files;
        try {
            files = plot(run, o);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        lua_pushstring(L, files.png.c_str());
        lua_pushstring(L, files.script.c_str());
        lua_pushstring(L, files.data.c_str());
        return 3;
    });
}

int run_index(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        const RunMeta& m = run.meta();
        if (key == "dir") {
            lua_pushstring(L, run.dir().c_str());
        } else if (key == "name") {
            lua_pushstring(L, m.name.c_str());
        } else if (key == "status") {
            lua_pushstring(L, m.status.c_str());
        } else if (key == "message") {
            lua_pushstring(L, m.message.c_str());
        } else if (key == "state") {
            lua_pushstring(L, run.state().c_str());
        } else if (key == "rows") {
            lua_pushinteger(L, run.rows());
        } else if (key == "truncated") {
            lua_pushboolean(L, run.truncated());
        } else if (key == "script") {
            lua_pushstring(L, m.script.c_str());
        } else if (key == "seed") {
            lua_pushinteger(L, static_cast<lua_Integer>(m.script_seed));
        } else if (key == "started") {
            lua_pushstring(L, m.started.c_str());
        } else if (key == "dt") {
            lua_pushnumber(L, m.options.dt);
        } else if (key == "provenance") {
            lua_createtable(L, 0, static_cast<int>(m.provenance.size()));
            for (const auto& [k, v] : m.provenance)
                set_string(L, k.c_str(), v);
        } else {
            raw_getfield(L, lua_upvalueindex(1), key);
        }
        return 1;
    });
}

int run_tostring(lua_State* L) {
    return protect(L, [&] {
        const RunData& run = check_run(L, 1);
        lua_pushfstring(L, "gaitlab.Run '%s' (%d series, %s)", run.dir().c_str(),
                        static_cast<int>(run.series().size()), run.meta().status.c_str());
        return 1;
    });
}

// live:get(name): { time = {...}, values = {...} }; live:get(): every series by name. The
// script runs on the simulation's thread: the samples taken since the last refresh are
// published first, so what it reads ends at the last sample
int live_get(lua_State* L) {
    return protect(L, [&] {
        LiveBuffers& b = check_live(L, 1);
        b.flush();
        std::vector<std::string> names;
        if (!lua_isnoneornil(L, 2)) names.push_back(check_string(L, 2));
        LiveSnapshot s;
        try {
            s = b.snapshot(names);
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        if (!names.empty()) {
            lua_createtable(L, 0, 2);
            push_numbers(L, s.time);
            lua_setfield(L, -2, "time");
            push_numbers(L, s.values[0]);
            lua_setfield(L, -2, "values");
            return 1;
        }
        lua_createtable(L, 0, static_cast<int>(s.names.size()) + 1);
        push_numbers(L, s.time);
        lua_setfield(L, -2, "time");
        for (size_t i = 0; i < s.names.size(); ++i) {
            push_numbers(L, s.values[i]);
            lua_setfield(L, -2, s.names[i].c_str());
        }
        return 1;
    });
}

int live_index(lua_State* L) {
    return protect(L, [&] {
        const LiveBuffers& b = check_live(L, 1);
        const std::string key = lua_type(L, 2) == LUA_TSTRING ? to_string(L, 2) : "";
        const LiveOptions o = b.options();
        if (key == "sample_every") {
            lua_pushinteger(L, o.sample_every);
        } else if (key == "refresh") {
            lua_pushnumber(L, o.refresh_seconds);
        } else if (key == "size") {
            lua_pushinteger(L, o.size);
        } else if (key == "version") {
            lua_pushinteger(L, static_cast<lua_Integer>(b.version()));
        } else if (key == "series") {
            push_strings(L, o.series);
        } else {
            raw_getfield(L, lua_upvalueindex(1), key);
        }
        return 1;
    });
}

int live_newindex(lua_State* L) {
    return protect(L, [&] {
        LiveBuffers& b = check_live(L, 1);
        const std::string key = check_string(L, 2);
        try {
            if (key == "sample_every") {
                const long long every = check_integer(L, 3);
                LiveBuffers::check_sample_every(every);
                b.set_sample_every(static_cast<int>(every));
            } else if (key == "refresh") {
                b.set_refresh_seconds(check_number(L, 3));
            } else if (key == "size") {
                const long long size = check_integer(L, 3);
                LiveBuffers::check_size(size);
                b.set_size(static_cast<int>(size));
            } else {
                throw Error(fmt::format("live buffers have no setting '{}'{}", key,
                                        did_you_mean(key, {"sample_every", "refresh", "size"})));
            }
        } catch (const ArgError& e) {
            throw Error(fmt::format("live.{}: {}", key, e.what()));
        }
        return 0;
    });
}

}  // namespace

// sim:live{ series = , sample_every = , refresh = , size = }
int live_new(lua_State* L) {
    return protect(L, [&] {
        const auto& h = check_object<SimulationHandle>(L, 1, kSimulationType);
        LiveOptions o;
        if (!lua_isnoneornil(L, 2)) {
            Fields f(L, 2, 2, {"series", "sample_every", "refresh", "size"});
            if (f.has("series")) {
                f.push("series");
                o.series = to_names(L, -1, 2, "field 'series': ");
                lua_pop(L, 1);
            }
            // checked as given before they become ints (1e12 was refused as -727379968)
            const long long every = f.integer("sample_every", 0);
            if (f.has("sample_every") && every < 1) f.fail("sample_every", "at least 1 expected");
            const long long size = f.integer("size", o.size);
            try {
                if (f.has("sample_every")) LiveBuffers::check_sample_every(every);
                LiveBuffers::check_size(size);
            } catch (const SpecError& e) {
                throw ArgError(2, e.what());
            }
            o.sample_every = static_cast<int>(every);
            o.refresh_seconds = f.number("refresh", o.refresh_seconds);
            o.size = static_cast<int>(size);
        }
        try {
            auto buffers = std::make_shared<LiveBuffers>(*h.sim, o);
            new_object<LiveHandle>(L, kLiveType, LiveHandle{h.sim, std::move(buffers)});
        } catch (const SpecError& e) {
            throw ArgError(2, e.what());
        }
        return 1;
    });
}

void open_data(lua_State* L) {
    const luaL_Reg run_methods[] = {
        {"series", run_series}, {"select", run_select}, {"get", run_get},   {"events", run_events},
        {"log", run_log},       {"export", run_export}, {"plot", run_plot}, {nullptr, nullptr}};
    const luaL_Reg run_meta[] = {{"__tostring", run_tostring}, {nullptr, nullptr}};
    register_type_with_fields<RunPtr>(L, kRunType, run_methods, run_index, run_meta);

    const luaL_Reg live_methods[] = {{"get", live_get}, {nullptr, nullptr}};
    const luaL_Reg live_meta[] = {{"__newindex", live_newindex}, {nullptr, nullptr}};
    register_type_with_fields<LiveHandle>(L, kLiveType, live_methods, live_index, live_meta);

    lua_createtable(L, 0, 1);
    lua_pushcfunction(L, data_open);
    lua_setfield(L, -2, "open");
    lua_setfield(L, -2, "data");
}

}  // namespace gaitlab::scripting
