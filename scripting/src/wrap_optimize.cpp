// gaitlab.optimize{ spec =, method =, generations =, population =, workers =, seed =, out =,
// resume = }: runs the optimization a spec file describes, as `gaitlab optimize` does, and
// returns the best. The runner sits above scripting: this file reads the table and the host's
// handler (LuaHost::set_optimize_handler, installed by the command line) checks the options with
// the command line's own checks and runs it.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "guard.h"
#include "lua_util.h"
#include "playback.h"
#include "wrap.h"

namespace gaitlab::scripting {

namespace {

// field `key` as decimal text for the handler's checks ("" : absent): an integer as it is, any
// other number as Lua would write it (the check then says a whole number was expected); with
// `text_too`, a string as it is (a seed past the 64-bit signed integers)
std::string number_text(lua_State* L, const Fields& f, const char* key, bool text_too = false) {
    const int t = f.push(key);
    std::string text;
    if (t == LUA_TNUMBER) {
        if (lua_isinteger(L, -1)) {
            text = std::to_string(lua_tointeger(L, -1));
        } else {
            const double d = lua_tonumber(L, -1);
            // a whole float (10.0) is the integer it holds
            text = std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9.2e18
                       ? std::to_string(static_cast<long long>(d))
                       : fmt::format("{}", d);
        }
    } else if (t == LUA_TSTRING && text_too) {
        text = to_string(L, -1);
    } else if (t != LUA_TNIL) {
        const std::string got = type_name(L, -1);
        lua_pop(L, 1);
        f.fail(key, std::string(text_too ? "integer (or a string of digits)" : "integer") +
                        " expected, got " + got);
    }
    lua_pop(L, 1);
    return text;
}

void push_result(lua_State* L, const LuaHost::OptimizeResult& r) {
    lua_createtable(L, 0, 10);
    lua_createtable(L, 0, static_cast<int>(r.parameters.size()));
    for (const auto& p : r.parameters) {
        if (p.integer) {
            lua_pushinteger(L, static_cast<lua_Integer>(std::llround(p.value)));
        } else {
            lua_pushnumber(L, p.value);
        }
        raw_setfield(L, -2, p.name.c_str());
    }
    raw_setfield(L, -2, "parameters");
    lua_pushnumber(L, r.fitness);
    raw_setfield(L, -2, "fitness");
    lua_pushinteger(L, r.evaluations);
    raw_setfield(L, -2, "evaluations");
    lua_pushstring(L, r.method.c_str());
    raw_setfield(L, -2, "method");
    lua_pushinteger(L, r.generations);
    raw_setfield(L, -2, "generations");
    lua_pushinteger(L, r.population);
    raw_setfield(L, -2, "population");
    // the files that could not be made stay nil (the results folder's best.json says why)
    const std::pair<const char*, const std::string*> paths[] = {
        {"folder", &r.folder}, {"simulation", &r.simulation}, {"run", &r.run}, {"plot", &r.plot}};
    for (const auto& [key, path] : paths) {
        if (path->empty()) continue;
        lua_pushlstring(L, path->data(), path->size());
        raw_setfield(L, -2, key);
    }
}

int optimize(lua_State* L) {
    return protect(L, [&] {
        LuaHost::OptimizeRequest request;
        {
            Fields f(L, 1, 1,
                     {"spec", "method", "generations", "population", "workers", "seed", "out",
                      "resume"});
            const int t = f.push("spec");
            if (t == LUA_TSTRING) request.spec = to_string(L, -1);
            lua_pop(L, 1);
            if (t == LUA_TTABLE) {
                // a spec's functions (build, fitness) belong to this Lua state: no worker could
                // call them
                f.fail("spec",
                       "a spec file expected (spec = \"SPEC.lua\"), got a table: each worker "
                       "loads the spec file into a Lua state of its own, and the functions of a "
                       "table cannot move between Lua states (put the table in a file that "
                       "returns it)");
            }
            if (t != LUA_TSTRING) {
                f.fail("spec", "a spec file expected (spec = \"SPEC.lua\"), got " +
                                   std::string(lua_typename(L, t)));
            }
            if (request.spec.empty()) f.fail("spec", "a spec file expected, got \"\"");
            request.spec = script_path(L, request.spec);
            request.method = f.string("method", "");
            if (f.has("method") && request.method.empty()) {
                f.fail("method", "ga, cmaes or pgpe expected, got \"\"");
            }
            request.generations = number_text(L, f, "generations");
            request.population = number_text(L, f, "population");
            request.workers = number_text(L, f, "workers");
            request.seed = number_text(L, f, "seed", true);
            // a results folder is a run folder: relative to the current folder (the spec file
            // is read relative to the script's, as files scripts load are)
            request.out = f.string("out", "");
            if (f.has("out") && request.out.empty()) f.fail("out", "a folder expected, got \"\"");
            if (request.out.find('\0') != std::string::npos) {
                f.fail("out", "a folder expected: a path cannot contain a zero byte");
            }
            request.resume = f.boolean("resume", false);
        }
        const Playback& playback = Playback::of(L);
        if (!playback.optimize) {
            throw Error(
                "gaitlab.optimize: no optimizer here: call it from a script run by gaitlab run "
                "FILE.lua or in the console (gaitlab, gaitlab -i FILE.lua), or run the spec "
                "with gaitlab optimize SPEC.lua");
        }
        request.stop = &Guard::of(L).interrupt_signal();
        LuaHost::OptimizeResult result;
        try {
            result = playback.optimize(request);
        } catch (const FieldError& e) {
            throw ArgError(1, "field '" + e.key() + "': " + e.what());
        }
        push_result(L, result);
        return 1;
    });
}

}  // namespace

void open_optimize(lua_State* L) {
    lua_pushcfunction(L, optimize);
    lua_setfield(L, -2, "optimize");
}

}  // namespace gaitlab::scripting
