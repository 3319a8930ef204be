// gaitlab.optimize{...} (scripting/src/wrap_optimize.cpp): what reaches the host's handler from
// the table (the spec resolved against the script's folder, the options as text for the
// command line's checks, the host's interrupt), what the script gets back, and the errors: a
// bad field found by the handler, no handler at all. The optimization itself, through the
// command line's handler: tests/cli/optimize_lua_test.cpp.
#include <catch2/catch.hpp>

#include <csignal>
#include <string>

#include "lua_fixture.h"
#include "temp_dir.h"

using gaitlab::Error;
using gaitlab::scripting::FieldError;
using gaitlab::scripting::LuaHost;
using gaitlab::test::LuaFixture;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

LuaHost::OptimizeResult a_result() {
    LuaHost::OptimizeResult r;
    r.parameters = {{"amplitude", 42.5, false}, {"modules", 3, true}};
    r.fitness = 0.25;
    r.evaluations = 16;
    r.method = "cmaes";
    r.generations = 2;
    r.population = 8;
    r.folder = "/somewhere/out";
    r.simulation = "/somewhere/out/best/best.xml";  // no run, no plot
    return r;
}

}  // namespace

TEST_CASE("gaitlab.optimize: the table reaches the handler, the result the script", "[optimize]") {
    LuaFixture lua;
    LuaHost::OptimizeRequest seen;
    int calls = 0;
    lua.host.set_optimize_handler([&](const LuaHost::OptimizeRequest& r) {
        seen = r;
        ++calls;
        return a_result();
    });
    lua.run(
        "r = gaitlab.optimize{ spec = 'spec.lua', method = 'ga', generations = 3, "
        "population = 10.0, workers = 2, seed = '18446744073709551615', out = 'o', resume = "
        "true }");
    CHECK(calls == 1);
    CHECK(seen.spec == "spec.lua");  // a typed chunk has no folder: as given
    CHECK(seen.method == "ga");
    CHECK(seen.generations == "3");
    CHECK(seen.population == "10");  // a whole float is its integer
    CHECK(seen.workers == "2");
    CHECK(seen.seed == "18446744073709551615");
    CHECK(seen.out == "o");
    CHECK(seen.resume);
    CHECK(lua.number("r.parameters.amplitude") == 42.5);
    CHECK(lua.integer("r.parameters.modules") == 3);
    CHECK(lua.string("math.type(r.parameters.modules)") == "integer");
    CHECK(lua.number("r.fitness") == 0.25);
    CHECK(lua.integer("r.evaluations") == 16);
    CHECK(lua.string("r.method") == "cmaes");
    CHECK(lua.integer("r.generations") == 2);
    CHECK(lua.integer("r.population") == 8);
    CHECK(lua.string("r.folder") == "/somewhere/out");
    CHECK(lua.string("r.simulation") == "/somewhere/out/best/best.xml");
    CHECK(lua.boolean("r.run == nil and r.plot == nil"));

    // not given: empty, for the handler's defaults; a fractional number stays one (the
    // handler's check refuses it)
    lua.run("gaitlab.optimize{ spec = 'spec.lua', generations = 2.5 }");
    CHECK(seen.method.empty());
    CHECK(seen.generations == "2.5");
    CHECK(seen.population.empty());
    CHECK(seen.workers.empty());
    CHECK(seen.seed.empty());
    CHECK(seen.out.empty());
    CHECK_FALSE(seen.resume);

    // the stop flag is the host's interrupt
    REQUIRE(seen.stop != nullptr);
    CHECK(seen.stop->load() == 0);
    lua.host.interrupt(SIGINT);
    CHECK(seen.stop->load() == SIGINT);
    lua.host.clear_interrupt();
    CHECK(seen.stop->load() == 0);
}

TEST_CASE("gaitlab.optimize: a spec file relative to the calling script's folder", "[optimize]") {
    TempDir dir("wrap_optimize");
    LuaHost host;
    std::string spec;
    host.set_optimize_handler([&](const LuaHost::OptimizeRequest& r) {
        spec = r.spec;
        return a_result();
    });
    write_text(dir / "script.lua", "gaitlab.optimize{ spec = 'specs/speed.lua' }\n");
    host.run_file(dir / "script.lua");
    CHECK(spec == dir / "specs/speed.lua");
}

TEST_CASE("gaitlab.optimize: the handler's errors, and no handler", "[optimize]") {
    LuaFixture lua;
    // no handler (a C++ program's own host, lua5.4's require "gaitlab"): where there is one
    CHECK(lua.error_of("gaitlab.optimize{ spec = 'spec.lua' }") ==
          "test:1: gaitlab.optimize: no optimizer here: call it from a script run by gaitlab "
          "run FILE.lua or in the console (gaitlab, gaitlab -i FILE.lua), or run the spec with "
          "gaitlab optimize SPEC.lua");
    // the table is checked first, handler or not
    CHECK(
        lua.error_of("gaitlab.optimize{ spec = {} }")
            .rfind(
                "test:1: bad argument #1 to 'optimize' (field 'spec': a spec file expected (spec = "
                "\"SPEC.lua\"), got a table: each worker loads the spec file into a Lua state of "
                "its own",
                0) == 0);
    // a bad option the handler finds is the table's field, at the caller's line
    lua.host.set_optimize_handler([](const LuaHost::OptimizeRequest& r) -> LuaHost::OptimizeResult {
        if (r.generations == "0") throw FieldError("generations", "at least 1 expected");
        throw Error("spec.lua: fitness: missing");
    });
    CHECK(lua.error_of("local a = 1\ngaitlab.optimize{ spec = 's.lua', generations = 0 }") ==
          "test:2: bad argument #1 to 'optimize' (field 'generations': at least 1 expected)");
    CHECK(lua.error_of("gaitlab.optimize{ spec = 's.lua' }") ==
          "test:1: spec.lua: fitness: missing");
    // the handler goes: no optimizer again
    lua.host.set_optimize_handler({});
    CHECK(lua.error_of("gaitlab.optimize{ spec = 's.lua' }")
              .rfind("test:1: gaitlab.optimize: no optimizer here", 0) == 0);
}
