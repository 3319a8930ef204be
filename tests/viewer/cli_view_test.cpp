// gaitlab run --view from the command line: bad options and a port in use give one clear line
// and a non-zero status, before the script runs.
#include <string>

#include <catch2/catch.hpp>

#include "cli/run_gaitlab.h"
#include "gaitlab/viewer/server.h"

using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;

namespace {

std::string walk() {
    return std::string(GAITLAB_SOURCE_DIR) + "/tests/viewer/scripts/walk.lua";
}

}  // namespace

TEST_CASE("gaitlab run --view: a port in use says so and how to choose another") {
    TempDir dir("cli_view");
    gaitlab::viewer::Server taken({});
    const std::string port = std::to_string(taken.port());
    const auto r = run_gaitlab({"run", walk(), "--view", "--port", port, "--no-record"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err == "gaitlab: cannot serve the viewer on 127.0.0.1:" + port + ": port " + port +
                       " is in use (choose another with --port N, or leave --port out for any "
                       "free port)\n");
    CHECK(r.out.empty());  // the script did not run
}

TEST_CASE("gaitlab run --view: bad --port and --host values are refused") {
    TempDir dir("cli_view");
    for (const char* bad : {"abc", "0", "65536", "-3", "80.5"}) {
        const auto r = run_gaitlab({"run", walk(), "--view", "--port", bad}, dir.str());
        INFO(bad << ": " << r.err);
        CHECK(r.status == 2);
        CHECK(r.err.find("--port: a port number from 1 to 65535 expected (got '") !=
              std::string::npos);
    }
    const auto host = run_gaitlab({"run", walk(), "--view", "--host", "192.0.2.1"}, dir.str());
    CHECK(host.status == 1);
    CHECK(host.err.find("'192.0.2.1' is not an address of this machine") != std::string::npos);
    // --port and --host mean nothing without --view
    const auto alone = run_gaitlab({"run", walk(), "--port", "8080"}, dir.str());
    CHECK(alone.status == 2);
    CHECK(alone.err.find("--port requires --view") != std::string::npos);
}
