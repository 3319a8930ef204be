// Parameter sweeps (optimize/runner/src/sweep.cpp): the grid read from --grid arguments and
// every bad form of them, the points in grid order, the results folder (table, jsonl, best,
// PNG decoded) with the known best point winning, failed points, 1 and 2 workers alike.
#include <catch2/catch.hpp>

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/optimize/sweep.h"
#include "temp_dir.h"

using gaitlab::optimize::Grid;
using gaitlab::optimize::load_spec;
using gaitlab::optimize::parse_grid;
using gaitlab::optimize::run_sweep;
using gaitlab::optimize::Spec;
using gaitlab::optimize::SweepOptions;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

// quick evaluations: an empty world for a few steps, and a fitness whose best on the grid below
// is a = 0.3, b = 4 (plus c, off the grid at its initial 0.25); a = 0.5, b = 2 fails
const std::string kSpec = R"(return {
  parameters = { a = {0, 1}, b = {0, 10, integer = true}, c = {0, 1, initial = 0.25} },
  build = function(p)
    return gaitlab.simulation{ world = gaitlab.world{} }
  end,
  fitness = function(sim, p)
    if p.a == 0.5 and p.b == 2 then error("no gait here") end
    return -(p.a - 0.3) ^ 2 - (p.b - 4) ^ 2 + p.c
  end,
  duration = 0.01,
}
)";

std::vector<std::string> lines(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
        out.push_back(line);
    return out;
}

// evaluations.jsonl without the fields that depend on timing and on the workers
std::vector<std::string> timeless(const std::string& path) {
    std::vector<std::string> out;
    for (const std::string& line : lines(read_text(path))) {
        std::string l = line;
        const auto s = l.find(",\"seconds\":");
        const auto e = l.find(",\"error\":");
        l = l.substr(0, s) + (e == std::string::npos ? "" : l.substr(e));
        out.push_back(l);
    }
    return out;
}

std::string grid_error(const Spec& spec, const std::vector<std::string>& args) {
    try {
        parse_grid(spec, args);
    } catch (const gaitlab::SpecError& e) {
        return e.what();
    }
    return "(no error)";
}

struct Png {
    unsigned width = 0, height = 0;
    std::vector<unsigned char> rgba;
};

Png load_png(const std::string& path) {
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&img, path.c_str()) != 0);
    img.format = PNG_FORMAT_RGBA;
    Png out;
    out.width = img.width;
    out.height = img.height;
    out.rgba.resize(PNG_IMAGE_SIZE(img));
    REQUIRE(png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr) != 0);
    return out;
}

// how many different colours the image has: a plot has axes, text and, for a heat map, cells
std::size_t colours(const Png& png) {
    std::vector<std::uint32_t> seen;
    for (std::size_t i = 0; i + 3 < png.rgba.size(); i += 4) {
        const std::uint32_t c = static_cast<std::uint32_t>(png.rgba[i]) << 16 |
                                static_cast<std::uint32_t>(png.rgba[i + 1]) << 8 | png.rgba[i + 2];
        if (std::find(seen.begin(), seen.end(), c) == seen.end()) seen.push_back(c);
        if (seen.size() > 1000) break;
    }
    return seen.size();
}

}  // namespace

TEST_CASE("a grid holds FROM, FROM + STEP ... TO, the first axis varying slowest") {
    TempDir dir("sweep_grid");
    write_text(dir / "spec.lua", kSpec);
    const Spec spec = load_spec(dir / "spec.lua");
    const Grid g = parse_grid(spec, {"b=1:5:2", "a=0:1:0.1"});
    REQUIRE(g.axes.size() == 2);
    CHECK(g.axes[0].parameter == 1);  // b
    CHECK(g.axes[0].values == std::vector<double>{1, 3, 5});
    // whole units of the last decimal: 0.3, not 0.30000000000000004
    CHECK(g.axes[1].values ==
          std::vector<double>{0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1});
    CHECK(g.points() == 33);
    // off the grid: c at its initial value; a (no initial) at its range's centre
    CHECK(g.base == std::vector<double>{0.5, 5, 0.25});
    CHECK(g.point(0) == std::vector<double>{0, 1, 0.25});
    CHECK(g.point(1) == std::vector<double>{0.1, 1, 0.25});
    CHECK(g.point(11) == std::vector<double>{0, 3, 0.25});
    CHECK(g.point(32) == std::vector<double>{1, 5, 0.25});
    // a TO the steps do not reach: the last value below it
    CHECK(parse_grid(spec, {"a=0:1:0.3"}).axes[0].values == std::vector<double>{0, 0.3, 0.6, 0.9});
    CHECK(parse_grid(spec, {"a=0.25:0.75:0.25"}).axes[0].values ==
          std::vector<double>{0.25, 0.5, 0.75});
    CHECK(parse_grid(spec, {"a=0:1:1e-1"}).axes[0].values.size() == 11);
}

TEST_CASE("bad --grid arguments are refused naming the argument and what is expected") {
    TempDir dir("sweep_grid_bad");
    write_text(dir / "spec.lua", kSpec);
    const Spec spec = load_spec(dir / "spec.lua");
    const std::string syntax = "NAME=FROM:TO:STEP expected, e.g. phase=30:180:15";
    CHECK(grid_error(spec, {}) == "--grid: at least one " + syntax + " (a, b, c)");
    CHECK(grid_error(spec, {"a"}) == "--grid 'a': " + syntax);
    CHECK(grid_error(spec, {"=0:1:0.1"}) == "--grid '=0:1:0.1': " + syntax);
    CHECK(grid_error(spec, {"a=0:1"}) == "--grid 'a=0:1': " + syntax);
    CHECK(grid_error(spec, {"a=0:1:0.1:2"}) == "--grid 'a=0:1:0.1:2': " + syntax);
    CHECK(grid_error(spec, {"a=0:x:0.1"}) ==
          "--grid 'a=0:x:0.1': TO: a number expected, got 'x' (" + syntax + ")");
    CHECK(grid_error(spec, {"a=0:1:nan"}) ==
          "--grid 'a=0:1:nan': STEP: a number expected, got 'nan' (" + syntax + ")");
    CHECK(grid_error(spec, {"aa=0:1:0.1"}) ==
          "--grid 'aa=0:1:0.1': unknown parameter 'aa'; did you mean 'a'? (the spec's "
          "parameters: a, b, c)");
    CHECK(grid_error(spec, {"a=0:1:0.5", "a=0:1:0.1"}) == "--grid 'a=0:1:0.1': 'a' is swept twice");
    CHECK(grid_error(spec, {"a=0:1:0"}) == "--grid 'a=0:1:0': STEP 0: a step > 0 expected");
    CHECK(grid_error(spec, {"a=0:1:-0.1"}) ==
          "--grid 'a=0:1:-0.1': STEP -0.1: a step > 0 expected");
    CHECK(grid_error(spec, {"a=0.5:0.5:0.1"}) ==
          "--grid 'a=0.5:0.5:0.1': the range 0.5:0.5 is empty (FROM < TO expected)");
    CHECK(grid_error(spec, {"a=1:0:0.1"}) ==
          "--grid 'a=1:0:0.1': the range 1:0 is inverted (FROM < TO expected)");
    CHECK(grid_error(spec, {"a=0:0.5:1"}) ==
          "--grid 'a=0:0.5:1': STEP 1 is larger than the range 0:0.5: one value (a smaller "
          "step expected)");
    CHECK(grid_error(spec, {"a=-0.5:1:0.5"}) ==
          "--grid 'a=-0.5:1:0.5': -0.5 is outside a's range [0, 1] in " + (dir / "spec.lua"));
    CHECK(grid_error(spec, {"b=0:12:2"}) ==
          "--grid 'b=0:12:2': 12 is outside b's range [0, 10] in " + (dir / "spec.lua"));
    CHECK(grid_error(spec, {"b=0:10:2.5"}) ==
          "--grid 'b=0:10:2.5': 'b' is an integer parameter: whole numbers expected for FROM "
          "and STEP");
    // too large: 100 000 points at most, on one axis or in all
    CHECK(grid_error(spec, {"a=0:1:1e-6"}) ==
          "--grid 'a=0:1:1e-6': 1000001 values on one axis; a grid has at most 100000 points");
    CHECK(grid_error(spec, {"a=0:1:0.001", "c=0:1:0.001"}) ==
          "--grid: 1001 x 1001 = 1002001 points; a grid has at most 100000");
    CHECK(parse_grid(spec, {"a=0:0.999:0.001", "c=0:0.99:0.01"}).points() == 100000);
}

TEST_CASE("a sweep evaluates every point, the best wins, a failed point is marked") {
    TempDir dir("sweep_run");
    write_text(dir / "spec.lua", kSpec);
    const Spec spec = load_spec(dir / "spec.lua");
    const Grid grid = parse_grid(spec, {"a=0:1:0.1", "b=1:5:1"});
    SweepOptions o;
    o.workers = 2;
    o.out = dir / "two";
    o.command = "gaitlab sweep spec.lua";
    const auto r = run_sweep(spec, grid, o);
    CHECK(r.points == 55);
    CHECK(r.failed == 1);
    CHECK(r.first_error == dir / "spec.lua" + ":7: no gait here");
    REQUIRE(r.best == std::vector<double>{0.3, 4, 0.25});
    CHECK(r.best_fitness == 0.25);
    CHECK(r.best_point == 3 * 5 + 3);
    // the table: a header, then one row per point in grid order
    const std::vector<std::string> table = lines(read_text(dir / "two/sweep.csv"));
    REQUIRE(table.size() == 56);
    CHECK(table[0] == "a,b,fitness,error");
    CHECK(table[1] == "0,1,-8.84,");
    CHECK(table[2] == "0,2,-3.84,");
    CHECK(table[19] == "0.3,4,0.25,");
    CHECK(table[27] == "0.5,2,NaN," + dir / "spec.lua" + ":7: no gait here");
    CHECK(table[55] == "1,5,-1.24,");
    for (std::size_t i = 1; i < table.size(); ++i) {
        const double a = static_cast<double>((i - 1) / 5) / 10,
                     b = static_cast<double>((i - 1) % 5 + 1);
        CHECK(table[i].rfind(fmt::format("{},{},", a, b), 0) == 0);
    }
    // evaluations.jsonl as optimize writes it: every parameter, grid order
    const std::vector<std::string> jsonl = lines(read_text(dir / "two/evaluations.jsonl"));
    REQUIRE(jsonl.size() == 55);
    CHECK(jsonl[18].rfind("{\"generation\":0,\"individual\":18,\"parameters\":{\"a\":0.3,\"b\":4,"
                          "\"c\":0.25},\"fitness\":0.25,\"seconds\":",
                          0) == 0);
    CHECK(jsonl[26].find("\"fitness\":null") != std::string::npos);
    CHECK(jsonl[26].find("\"error\":\"" + dir / "spec.lua" + ":7: no gait here\"") !=
          std::string::npos);
    // best.json and the best as a simulation file
    const std::string best = read_text(dir / "two/best.json");
    CHECK(best.find("\"method\": \"sweep\"") != std::string::npos);
    CHECK(best.find("\"fitness\": 0.25,") != std::string::npos);
    CHECK(best.find("\"a\": 0.3,\n    \"b\": 4,\n    \"c\": 0.25") != std::string::npos);
    CHECK(best.find("\"failed\": 1,") != std::string::npos);
    CHECK(std::filesystem::exists(dir / "two/best/best.xml"));
    CHECK(r.simulation == dir / "two/best/best.xml");
    // the heat map: a PNG of the script's size with many colours (cells, palette)
    REQUIRE(r.plot == dir / "two/sweep.png");
    const Png png = load_png(r.plot);
    CHECK(png.width == 1000);
    CHECK(png.height == 700);
    CHECK(colours(png) > 50);
    CHECK(read_text(dir / "two/sweep.gp").find("using 1:2:3 skip 1 with image") !=
          std::string::npos);

    // one worker: the same table and evaluations
    o.workers = 1;
    o.out = dir / "one";
    run_sweep(spec, grid, o);
    CHECK(read_text(dir / "one/sweep.csv") == read_text(dir / "two/sweep.csv"));
    CHECK(timeless(dir / "one/evaluations.jsonl") == timeless(dir / "two/evaluations.jsonl"));
    // the results folder is never overwritten
    CHECK_THROWS_WITH(run_sweep(spec, grid, o),
                      Catch::Contains("the folder exists and is not empty"));
}

TEST_CASE("a sweep over one parameter draws a line plot, over three, none") {
    TempDir dir("sweep_axes");
    write_text(dir / "spec.lua", kSpec);
    const Spec spec = load_spec(dir / "spec.lua");
    SweepOptions o;
    o.out = dir / "line";
    const auto r = run_sweep(spec, parse_grid(spec, {"b=0:10:1"}), o);
    CHECK(r.best == std::vector<double>{0.5, 4, 0.25});
    REQUIRE(r.plot == dir / "line/sweep.png");
    CHECK(load_png(r.plot).width == 1000);
    CHECK(read_text(dir / "line/sweep.gp").find("with linespoints") != std::string::npos);
    CHECK(lines(read_text(dir / "line/sweep.csv"))[0] == "b,fitness,error");

    o.out = dir / "three";
    const auto r3 = run_sweep(spec, parse_grid(spec, {"a=0:1:0.5", "b=3:5:1", "c=0:1:0.5"}), o);
    CHECK(r3.points == 27);
    CHECK(r3.best == std::vector<double>{0.5, 4, 1});
    CHECK(r3.plot.empty());
    CHECK(r3.plot_error == "no plot for 3 swept parameters (one: a line plot, two: a heat map)");
    CHECK_FALSE(std::filesystem::exists(dir / "three/sweep.png"));
    CHECK(lines(read_text(dir / "three/sweep.csv")).size() == 28);
}

TEST_CASE("a sweep whose every point fails writes its table and no best") {
    TempDir dir("sweep_fails");
    write_text(dir / "spec.lua",
               "return { parameters = { a = {0, 1} }, fitness = 'speed',\n"
               "  duration = 1, build = function(p) error('cannot build') end }\n");
    const Spec spec = load_spec(dir / "spec.lua");
    SweepOptions o;
    o.out = dir / "out";
    const auto r = run_sweep(spec, parse_grid(spec, {"a=0:1:0.5"}), o);
    CHECK(r.failed == 3);
    CHECK(r.best.empty());
    CHECK(std::isnan(r.best_fitness));
    CHECK(r.plot_error == "no plot: every point failed");
    CHECK(lines(read_text(dir / "out/sweep.csv"))[1] ==
          "0,NaN," + dir / "spec.lua" + ":2: cannot build");
    CHECK(read_text(dir / "out/best.json").find("\"parameters\": null") != std::string::npos);
}

TEST_CASE("examples/optimize/snake_sweep.lua takes the grid its comment shows") {
    const Spec spec = load_spec(GAITLAB_SOURCE_DIR "/examples/optimize/snake_sweep.lua");
    const Grid g = parse_grid(spec, {"phase=0:180:15", "frequency=0.25:1:0.25"});
    CHECK(g.points() == 13 * 4);
    CHECK(g.point(0) == std::vector<double>{40, 0.25, 0});  // amplitude, frequency, phase
    CHECK(g.point(51) == std::vector<double>{40, 1, 180});
}

TEST_CASE("the seed seeds math.random before every evaluation, for any number of workers") {
    TempDir dir("sweep_seed");
    write_text(dir / "spec.lua",
               "return { parameters = { a = {0, 1} }, duration = 0.01,\n"
               "  build = function(p) return gaitlab.simulation{ world = gaitlab.world{} } end,\n"
               "  fitness = function(sim, p) return math.random() end }\n");
    const Spec spec = load_spec(dir / "spec.lua");
    const Grid grid = parse_grid(spec, {"a=0:1:0.5"});
    const auto table = [&](std::uint64_t seed, int workers, const std::string& out) {
        SweepOptions o;
        o.seed = seed;
        o.workers = workers;
        o.out = dir / out;
        run_sweep(spec, grid, o);
        return lines(read_text(dir / out + "/sweep.csv"));
    };
    const std::vector<std::string> zero = table(0, 1, "zero");
    REQUIRE(zero.size() == 4);
    // the same draw before every evaluation: each point's fitness is the seed's first number
    CHECK(zero[1].substr(2) == zero[2].substr(4));
    CHECK(table(0, 2, "zero2") == zero);
    const std::vector<std::string> seven = table(7, 1, "seven");
    CHECK(seven != zero);
    CHECK(table(7, 2, "seven2") == seven);
    CHECK(read_text(dir / "seven/best.json").find("\"seed\": 7,") != std::string::npos);
}

TEST_CASE("odd parameter names reach the table and the plot as data") {
    TempDir dir("sweep_names");
    write_text(dir / "spec.lua",
               "return { parameters = { ['a,\"b\"\\n`c`'] = {0, 1} }, duration = 0.01,\n"
               "  build = function(p) return gaitlab.simulation{ world = gaitlab.world{} } end,\n"
               "  fitness = function(sim, p) return p['a,\"b\"\\n`c`'] end }\n");
    const Spec spec = load_spec(dir / "spec.lua");
    SweepOptions o;
    o.out = dir / "out";
    const auto r = run_sweep(spec, parse_grid(spec, {"a,\"b\"\n`c`=0:1:0.5"}), o);
    CHECK(r.best == std::vector<double>{1});
    CHECK(read_text(dir / "out/sweep.csv").rfind("\"a,\"\"b\"\"\n`c`\",fitness,error\n0,0,\n", 0) ==
          0);
    REQUIRE(r.plot == dir / "out/sweep.png");  // gnuplot ran the script
    CHECK(read_text(dir / "out/sweep.gp").find("skip 2") != std::string::npos);
}
