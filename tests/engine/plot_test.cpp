// Plots (engine/src/plot.cpp): a PNG drawn by gnuplot, checked by decoding it, with its gnuplot
// script and data kept next to it.
#include <catch2/catch.hpp>

#include <png.h>

#include <cstdio>
#include <filesystem>
#include <set>

#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "sim_support.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;

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
