// Plots (engine/src/record/plot.cpp): a PNG drawn by gnuplot, checked by decoding it, with its
// gnuplot script and data kept next to it.
#include <catch2/catch.hpp>

#include <png.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

#include "engine/sim_support.h"
#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;

namespace {

struct Image {
    unsigned width = 0, height = 0;
    std::vector<std::uint32_t> rgba;
};

Image load_png(const std::string& path) {
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&img, path.c_str()) != 0);
    img.format = PNG_FORMAT_RGBA;
    Image out;
    out.width = img.width;
    out.height = img.height;
    out.rgba.resize(static_cast<size_t>(img.width) * img.height);
    REQUIRE(png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr) != 0);
    return out;
}

}  // namespace

TEST_CASE("a plot is a PNG of the asked size with curves on it", "[plot]") {
    TempDir tmp("plot_png");
    const RunData run(test::record_run(tmp / "run", 2));
    PlotOptions o;
    o.output = tmp / "out/angles.png";
    o.series = {"snake.angle[*]", "sine.angle[1]"};
    o.width = 800;
    o.height = 500;
    const PlotFiles f = plot(run, o);
    CHECK(f.png == tmp / "out/angles.png");
    CHECK(f.script == tmp / "out/angles.gp");
    CHECK(f.data == tmp / "out/angles.csv");
    const Image img = load_png(f.png);
    CHECK(img.width == 800);
    CHECK(img.height == 500);
    // not blank: many pixels differ from the background and there are several colours
    std::set<std::uint32_t> colours(img.rgba.begin(), img.rgba.end());
    CHECK(colours.size() > 20);
    size_t ink = 0;
    for (std::uint32_t p : img.rgba)
        ink += p != img.rgba[0];
    CHECK(ink > img.rgba.size() / 50);

    // the script and its data redraw it by hand
    const std::string gp = read_text(f.script);
    CHECK_THAT(gp, Catch::Contains("set terminal pngcairo size 800,500"));
    CHECK_THAT(gp, Catch::Contains("plot \"angles.csv\" using 1:2"));
    CHECK_THAT(gp, Catch::Contains("title \"sine.angle[1]\""));
    CHECK_THAT(read_text(f.data), Catch::StartsWith("time,snake.angle[1],snake.angle[2],"));
    std::filesystem::remove(f.png);
    const std::string cmd = "cd " + (tmp / "out") + " && gnuplot angles.gp 2>/dev/null";
    REQUIRE(std::system(cmd.c_str()) == 0);
    CHECK(load_png(f.png).width == 800);
}

TEST_CASE("plot options are checked", "[plot]") {
    TempDir tmp("plot_bad");
    const RunData run(test::record_run(tmp / "run", 2));
    PlotOptions o;
    o.series = {"snake.com.x"};
    o.output = tmp / "plot.jpg";
    CHECK_THROWS_WITH(plot(run, o), "plot output must be a .png file (got '" + o.output + "')");
    o.output = tmp / "p.png";
    o.series = {"snake.comx"};
    CHECK_THROWS_WITH(plot(run, o),
                      "unknown series 'snake.comx'; did you mean 'snake.com.x', 'snake.com.y' or "
                      "'snake.com.z'?");
    o.series = {};
    CHECK_THROWS_WITH(plot(run, o), "nothing to plot: give at least one series");
    o.series = {"snake.com.x"};
    o.width = 5;
    CHECK_THROWS_WITH(plot(run, o), "plot size must be 100 to 10000 pixels each way (got 5x600)");
}

namespace {

// the files in `dir` and below, relative to it
std::set<std::string> files_in(const std::string& dir) {
    std::set<std::string> out;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
        out.insert(std::filesystem::relative(e.path(), dir).string());
    return out;
}

// replaces the robot name "placeholder" by `name` in the series names of `file` (a CSV file
// gaitlab wrote, whose fields need no quotes), quoting the new fields as RFC 4180 says
void rename_series(const std::string& file, const std::string& name) {
    std::istringstream in(read_text(file));
    std::string line, out;
    while (std::getline(in, line)) {
        std::string joined;
        for (size_t start = 0;;) {
            const size_t comma = line.find(',', start);
            std::string f = line.substr(start, comma == std::string::npos ? comma : comma - start);
            if (f == "placeholder" || f.rfind("placeholder.", 0) == 0) {
                f = name + f.substr(11);
                std::string quoted = "\"";
                for (char c : f)
                    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
                f = quoted + "\"";
            }
            joined += (start == 0 ? "" : ",") + f;
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        out += joined + "\n";
    }
    write_text(file, out);
}

// a recorded run whose robot's series carry the name `name`, as a run folder made elsewhere may
// (gaitlab itself records only names that are printable UTF-8)
std::string record_named(const std::string& dir, const std::string& name) {
    WorldSpec world = test::chain_world(2, Connection::pitch_pitch);
    world.robots[0].robot.name = "placeholder";
    Simulation sim(world);
    RecordOptions o;
    o.dir = dir;
    Recorder rec(sim, o);
    sim.run(0.1);
    rec.close();
    rename_series(dir + "/data.csv", name);
    rename_series(dir + "/series.csv", name);
    return dir;
}

}  // namespace

TEST_CASE("names in a plot are data: no name runs a command", "[plot]") {
    TempDir tmp("plot_hostile");
    // each of these would run `touch` through gnuplot if it reached the script as text:
    // backquotes, system(), quotes that end the string, line ends, macros, $ and backslashes
    const std::vector<std::string> hostile = {
        "s`touch bq1`",
        "a\" . system(\"touch sys1\") . \"",
        "a' . system('touch sys2') . '",
        "x\nset output \"/dev/null\"\n!touch nl1\n",
        "@mac `touch mac1` $0 \\\" \\",
        "\xff\xfe bad \xc3",
    };
    for (size_t k = 0; k < hostile.size(); ++k) {
        INFO("name " << k);
        const std::string work = tmp / ("w" + std::to_string(k));
        std::filesystem::create_directories(work);
        const RunData run(record_named(work + "/run", hostile[k]));
        PlotOptions o;
        // the title, the file names and the series names all hold the hostile text
        o.title = hostile[k];
        o.series = {hostile[k] + ".com.*", hostile[k] + ".angle[1]"};
        const std::string stem = "-p`touch fn1`$(touch fn2)'\"";
        o.output = work + "/out/" + stem + ".png";
        const PlotFiles f = plot(run, o);
        CHECK(load_png(f.png).width == 1000);
        // nothing but what gaitlab wrote: no file a command made, in the folder or the cwd
        std::set<std::string> files = files_in(work + "/out");
        CHECK(files == std::set<std::string>{stem + ".png", stem + ".gp", stem + ".csv"});
        for (const char* made : {"bq1", "sys1", "sys2", "nl1", "mac1", "fn1", "fn2"}) {
            CHECK_FALSE(std::filesystem::exists(work + "/out/" + made));
            CHECK_FALSE(std::filesystem::exists(made));
        }
        // the script holds no character gnuplot treats specially outside a string's escapes
        const std::string gp = read_text(f.script);
        for (char c : {'`', '$', '@', '\'', '!'})
            CHECK(gp.find(c) == std::string::npos);
        size_t lines = 0;
        for (char c : gp)
            lines += c == '\n';
        CHECK(lines == 10 + 7);  // comments, settings and one line per curve (7)
    }
}

TEST_CASE("a plot of a name with a line end still skips the whole header", "[plot]") {
    TempDir tmp("plot_newline");
    const RunData run(record_named(tmp / "run", "two\nlines"));
    PlotOptions o;
    o.series = {"two\nlines.com.x"};
    o.output = tmp / "p.png";
    const PlotFiles f = plot(run, o);
    CHECK_THAT(read_text(f.script), Catch::Contains("using 1:2 skip 2 with lines"));
    CHECK(load_png(f.png).height == 600);
}

namespace {

// sets the values of the series `name` in the data.csv of `dir` to `value`: every row, or the
// rows whose 0-based number has the parity `parity` (0 or 1)
void set_column(const std::string& dir, const std::string& name, const std::string& value,
                int parity = -1) {
    std::istringstream in(read_text(dir + "/data.csv"));
    std::string line, out;
    long column = -1;
    long row = 0;
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::stringstream ls(line);
        for (std::string f; std::getline(ls, f, ',');)
            fields.push_back(f);
        if (column < 0) {
            column = std::find(fields.begin(), fields.end(), name) - fields.begin();
            REQUIRE(column < static_cast<long>(fields.size()));
        } else if (parity < 0 || row++ % 2 == parity) {
            fields[static_cast<size_t>(column)] = value;
        }
        for (size_t i = 0; i < fields.size(); ++i)
            out += (i > 0 ? "," : "") + fields[i];
        out += "\n";
    }
    write_text(dir + "/data.csv", out);
}

}  // namespace

TEST_CASE("a path plot draws one series against another, at one scale", "[plot]") {
    TempDir tmp("plot_path");
    const RunData run(test::record_run(tmp / "run", 2));
    PlotOptions o;
    o.output = tmp / "out/path.png";
    o.x = "snake.com.x";
    o.y = "snake.com.y";
    o.from = 0.5;
    o.to = 1.5;
    const PlotFiles f = plot(run, o);
    CHECK(f.script == tmp / "out/path.gp");
    const Image img = load_png(f.png);
    CHECK(img.width == 1000);
    // the path itself: gnuplot's first line colour (purple, #9400d3) across most of the
    // plot's width (the legend's sample line is 40 pixels of it)
    size_t purple = 0;
    for (std::uint32_t p : img.rgba) {
        const unsigned r = p & 0xff, g = (p >> 8) & 0xff, b = (p >> 16) & 0xff;
        purple += b > 150 && r > 80 && g < 100;
    }
    CHECK(purple > 300);

    // the data: time, then the two series, the rows of the range and nothing else
    const SeriesData x = run.get("snake.com.x", 0.5, 1.5);
    std::istringstream csv(read_text(f.data));
    std::string line;
    std::getline(csv, line);
    CHECK(line == "time,snake.com.x,snake.com.y");
    size_t rows = 0;
    while (std::getline(csv, line)) {
        const double t = std::stod(line);
        CHECK(t >= 0.5);
        CHECK(t <= 1.5);
        if (rows == 0) {
            CHECK(std::stod(line.substr(line.find(',') + 1)) == x.values[0]);
        }
        ++rows;
    }
    CHECK(rows == x.time.size());
    CHECK(rows > 20);
    // the script: y against x, labelled with names and units, one scale, start and end marked
    const std::string gp = read_text(f.script);
    CHECK_THAT(gp,
               Catch::Contains("set xlabel \"snake.com.x (m)\"\nset ylabel \"snake.com.y (m)\"\n"
                               "set size ratio -1\n"));
    CHECK_THAT(gp, Catch::Contains("plot \"path.csv\" using 2:3 skip 1 with lines"));
    // this path is straight along x (a planar gait): y still gets a range a quarter of x's
    // wide, around the path, so the plot is a line in a box and its tick labels apart
    const auto range = [&](const std::string& axis) {
        const size_t at = gp.find("set " + axis + "range [");
        REQUIRE(at != std::string::npos);
        const size_t colon = gp.find(':', at);
        return std::pair{std::stod(gp.substr(gp.find('[', at) + 1)),
                         std::stod(gp.substr(colon + 1))};
    };
    const auto [x0, x1] = range("x");
    const auto [y0, y1] = range("y");
    const SeriesData y = run.get("snake.com.y", 0.5, 1.5);
    const auto [xmin, xmax] = std::minmax_element(x.values.begin(), x.values.end());
    const auto [ymin, ymax] = std::minmax_element(y.values.begin(), y.values.end());
    CHECK(*ymax - *ymin < 0.01 * (*xmax - *xmin));
    CHECK(x0 < *xmin);
    CHECK(x1 > *xmax);
    CHECK(y0 < *ymin);
    CHECK(y1 > *ymax);
    CHECK(y1 - y0 >= 0.25 * (*xmax - *xmin));
    CHECK(y1 - y0 < 0.3 * (x1 - x0));
    // one tick step on both axes, about six over the longer one
    const size_t xt = gp.find("set xtics "), yt = gp.find("set ytics ");
    REQUIRE(xt != std::string::npos);
    REQUIRE(yt != std::string::npos);
    const double step = std::stod(gp.substr(xt + 10));
    CHECK(std::stod(gp.substr(yt + 10)) == step);
    CHECK((x1 - x0) / step >= 3);
    CHECK((x1 - x0) / step <= 12);
    CHECK_THAT(gp, Catch::Contains("every ::0::0 with points"));
    CHECK_THAT(gp, Catch::Contains("every ::" + std::to_string(rows - 1) +
                                   "::" + std::to_string(rows - 1) + " with points"));

    // series of different units keep a scale each
    o.y = "snake.angle[1]";
    o.from = -RunData::kInf;
    o.to = RunData::kInf;
    const std::string gp2 = read_text(plot(run, o).script);
    CHECK_THAT(gp2, Catch::Contains("set ylabel \"snake.angle[1] (deg)\""));
    CHECK(gp2.find("set size ratio") == std::string::npos);
}

TEST_CASE("path plot options are checked", "[plot]") {
    TempDir tmp("plot_path_bad");
    const std::string dir = test::record_run(tmp / "run", 1);
    set_column(dir, "snake.com.z", "nan");
    const RunData run(dir);
    PlotOptions o;
    o.output = tmp / "out/p.png";
    o.x = "snake.com.x";
    CHECK_THROWS_WITH(plot(run, o), "a path plot needs two series: x and y");
    o.y = "snake.com.y";
    o.series = {"snake.com.z"};
    CHECK_THROWS_WITH(plot(run, o),
                      "a plot shows series against time or one series against another (x and "
                      "y), not both");
    o.series = {};
    o.x = "snake.com.*";
    CHECK_THROWS_WITH(plot(run, o),
                      "the x axis takes one series; 'snake.com.*' selects 6 (snake.com.x, "
                      "snake.com.y, snake.com.z, snake.com.vx, snake.com.vy, ...)");
    o.x = "snake.com.x";
    o.y = "snake.com.q";
    CHECK_THROWS_WITH(plot(run, o),
                      "unknown series 'snake.com.q'; did you mean 'snake.com.x', 'snake.com.y' or "
                      "'snake.com.z'?");
    o.y = "snake.com.x";
    CHECK_THROWS_WITH(plot(run, o), "x and y are the same series ('snake.com.x'): give two");
    o.y = "snake.com.z";
    CHECK_THROWS_WITH(plot(run, o),
                      "nothing to plot: 'snake.com.z' holds no numbers in the whole run (only NaN "
                      "or infinite values)");
    // numbers, but never in the same row
    const std::string dir2 = test::record_run(tmp / "run2", 0.3);
    set_column(dir2, "snake.com.x", "nan", 0);
    set_column(dir2, "snake.com.y", "inf", 1);
    PlotOptions o2 = o;
    o2.y = "snake.com.y";
    CHECK_THROWS_WITH(plot(RunData(dir2), o2),
                      "nothing to plot: 'snake.com.x' and 'snake.com.y' are never numbers at once "
                      "in the whole run");
    o.y = "snake.com.y";
    o.from = 5;
    CHECK_THROWS_WITH(plot(run, o), "nothing to plot: the run has no rows from 5 s on");
    o.from = 0.2;
    o.to = 0.1;
    CHECK_THROWS_WITH(plot(run, o), "nothing to plot: the run has no rows between 0.2 s and 0.1 s");
    // nothing was written for any of them
    CHECK_FALSE(std::filesystem::exists(tmp / "out"));
}

TEST_CASE("a path plot of extreme spans still draws: a point, and values near the double's limit",
          "[plot]") {
    TempDir tmp("plot_path_extreme");
    PlotOptions o;
    o.x = "snake.com.x";
    o.y = "snake.com.y";
    // one point: no span at all; the ranges and ticks stay finite numbers
    const std::string one = test::record_run(tmp / "one", 0.3);
    set_column(one, "snake.com.x", "0.25");
    set_column(one, "snake.com.y", "-0.5");
    o.output = tmp / "one.png";
    const std::string gp1 = read_text(plot(RunData(one), o).script);
    CHECK_THAT(gp1, Catch::Contains("set xrange [") && Catch::Contains("set xtics "));
    CHECK_THAT(gp1, !Catch::Contains("inf") && !Catch::Contains("nan"));
    // x from -1.7e308 to 1.7e308: its span is not a double, the script leaves the ranges to
    // gnuplot, which cannot draw it either: an error naming the script and data, not a crash
    const std::string huge = test::record_run(tmp / "huge", 0.3);
    set_column(huge, "snake.com.x", "-1.7e308", 0);
    set_column(huge, "snake.com.x", "1.7e308", 1);
    o.output = tmp / "huge.png";
    // the reason is gnuplot's last line (its complaint, naming the script's line), not the
    // command it echoes first
    CHECK_THROWS_WITH(
        plot(RunData(huge), o),
        Catch::StartsWith("gnuplot failed: \"./huge.gp\" line 14: x range is invalid") &&
            Catch::EndsWith("(the script and data are in " + (tmp / "huge.gp") + " and " +
                            (tmp / "huge.csv") + ")"));
    const std::string gp2 = read_text(tmp / "huge.gp");
    CHECK_THAT(gp2, !Catch::Contains("range [") && !Catch::Contains("tics "));
    CHECK_THAT(gp2, !Catch::Contains("inf") && !Catch::Contains("nan"));
}

TEST_CASE("names in a path plot are data: no name runs a command", "[plot]") {
    TempDir tmp("plot_path_hostile");
    const std::vector<std::string> hostile = {
        "s`touch bq1`",
        "a\" . system(\"touch sys1\") . \"",
        "x\nset output \"/dev/null\"\n!touch nl1\n",
        "@mac `touch mac1` $0 \\\" \\",
    };
    for (size_t k = 0; k < hostile.size(); ++k) {
        INFO("name " << k);
        const std::string work = tmp / ("w" + std::to_string(k));
        std::filesystem::create_directories(work);
        const RunData run(record_named(work + "/run", hostile[k]));
        PlotOptions o;
        o.title = hostile[k];
        o.x = hostile[k] + ".com.x";
        o.y = hostile[k] + ".com.y";
        const std::string stem = "-p`touch fn1`$(touch fn2)'\"";
        o.output = work + "/out/" + stem + ".png";
        const PlotFiles f = plot(run, o);
        CHECK(load_png(f.png).width == 1000);
        CHECK(files_in(work + "/out") ==
              std::set<std::string>{stem + ".png", stem + ".gp", stem + ".csv"});
        for (const char* made : {"bq1", "sys1", "nl1", "mac1", "fn1", "fn2"}) {
            CHECK_FALSE(std::filesystem::exists(work + "/out/" + made));
            CHECK_FALSE(std::filesystem::exists(made));
        }
        const std::string gp = read_text(f.script);
        for (char c : {'`', '$', '@', '\'', '!'})
            CHECK(gp.find(c) == std::string::npos);
        // the data holds the two columns under their names
        CHECK(read_text(f.data).rfind("time,", 0) == 0);
        CHECK(run.get(o.y).values.size() > 0);
    }
}

TEST_CASE("a table plot draws columns against the first, leaving out NaN", "[plot]") {
    TempDir tmp("plot_table");
    TablePlot t;
    t.output = tmp / "out/convergence.png";
    t.title = "spec.lua: speed";
    t.xlabel = "generation";
    t.ylabel = "speed";
    t.columns = {"generation", "best so far", "generation mean"};
    const double nan = std::numeric_limits<double>::quiet_NaN();
    t.rows = {{1, 0.5, 0.25}, {2, 0.75, nan}, {3, 0.75, 0.5}};
    t.width = 640;
    t.height = 400;
    const PlotFiles f = plot_table(t);
    CHECK(f.script == tmp / "out/convergence.gp");
    const Image img = load_png(f.png);
    CHECK(img.width == 640);
    CHECK(img.height == 400);
    std::set<std::uint32_t> colours(img.rgba.begin(), img.rgba.end());
    CHECK(colours.size() > 20);
    CHECK(read_text(f.data) ==
          "generation,best so far,generation mean\n1,0.5,0.25\n2,0.75,NaN\n3,0.75,0.5\n");
    const std::string gp = read_text(f.script);
    CHECK_THAT(gp, Catch::Contains("plot \"convergence.csv\" using 1:2 skip 1"));
    CHECK_THAT(gp, Catch::Contains("using 1:3 skip 1 with linespoints title \"generation mean\""));
}

TEST_CASE("table plot options are checked", "[plot]") {
    TempDir tmp("plot_table_bad");
    TablePlot t;
    t.output = tmp / "c.svg";
    t.columns = {"x", "y"};
    CHECK_THROWS_WITH(plot_table(t), "plot output must be a .png file (got '" + t.output + "')");
    t.output = tmp / "c.png";
    t.columns = {"x"};
    CHECK_THROWS_WITH(plot_table(t),
                      "a table plot needs an x column and at least one curve (got 1 columns)");
    t.columns = {"x", "y"};
    t.rows = {{1, 2}, {3}};
    CHECK_THROWS_WITH(plot_table(t), "table plot row 2: 2 values expected (one per column), got 1");
    t.rows = {{1, 2}};
    t.columns = {"x", "two\nlines"};
    CHECK_THROWS_WITH(plot_table(t), "table plot column 2: a name without line ends expected");
    t.columns = {"x", "y"};
    t.height = 20000;
    CHECK_THROWS_WITH(plot_table(t),
                      "plot size must be 100 to 10000 pixels each way (got 1000x20000)");
    CHECK_FALSE(std::filesystem::exists(tmp / "c.csv"));
}
