// Reading run folders (engine/src/run_data.cpp): lookup by name and by kind + value + joint,
// time ranges, a truncated last line, folders that are not runs, malformed files.
#include <catch2/catch.hpp>

#include <filesystem>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "sim_support.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
namespace fs = std::filesystem;

TEST_CASE("series by name, by kind + value + joint, and over a time range", "[run_data]") {
    TempDir tmp("run_data_get");
    RunData run(test::record_run(tmp / "run", 1));
    CHECK(run.rows() == 34);
    const SeriesData a = run.get("sine.angle[2]");
    REQUIRE(a.time.size() == 34);
    CHECK(a.info.kind == SeriesKind::controller);
    CHECK(a.info.joint == 2);
    CHECK(a.time[0] == 0);
    CHECK(a.time[33] == Approx(0.99));
    // the sine's own value: A sin(2 pi f t + (m - 1) phase) at the last control step
    CHECK(a.values[33] == Approx(40 * std::sin(2 * kPi * 0.5 * 0.99 + kPi * 120 / 180)));

    // before the first step no servo has acted (Bullet's feedback starts at zero)
    for (int j = 1; j <= 4; ++j)
        CHECK(run.get(fmt::format("snake.torque[{}]", j)).values[0] == 0);
    CHECK(run.find(SeriesKind::robot, "angle", 3).name == "snake.angle[3]");
    CHECK(run.find(SeriesKind::robot, "energy", 0).name == "snake.energy");
    CHECK(run.find(SeriesKind::controller, "amplitude", 0, "sine").name == "sine.amplitude");
    CHECK_THROWS_WITH(run.find(SeriesKind::robot, "angel", 3),
                      "no robot series 'angel' of joint 3; did you mean 'angle'?");
    CHECK_THROWS_WITH(run.find(SeriesKind::sensor, "range", 1),
                      "no sensor series 'range' of joint 1");

    const SeriesData r = run.get("snake.com.x", 0.25, 0.5);
    REQUIRE(r.time.size() == 8);  // 0.27, 0.30, ..., 0.48
    CHECK(r.time.front() == Approx(0.27));
    CHECK(r.time.back() == Approx(0.48));

    CHECK_THROWS_WITH(run.get("snake.angle[9]"),
                      "unknown series 'snake.angle[9]'; did you mean 'snake.angle[1]', "
                      "'snake.angle[2]' or 'snake.angle[3]'?");
    CHECK(run.select({"snake.angle[*]"}).size() == 4);
    CHECK(run.select({"controller"}).size() == 5 + 8);
    CHECK(run.select({"sine.amplitude", "sine.*"}).front() == "sine.amplitude");
    CHECK_THROWS_WITH(run.select({"sensor"}), "the run has no sensor series");
    CHECK_THROWS_WITH(run.select({"snake.com.q*"}),
                      "no series matches 'snake.com.q*'; did you mean 'snake.com.x', "
                      "'snake.com.y' or 'snake.com.z'?");

    run.write_csv(tmp / "two.csv", {"snake.com.x", "sine.amplitude"}, 0, 0.03);
    const std::string csv = read_text(tmp / "two.csv");
    CHECK_THAT(csv, Catch::StartsWith("time,snake.com.x,sine.amplitude\n0,"));
    CHECK_THAT(csv, Catch::EndsWith(",40\n"));
}

TEST_CASE("a last line cut short is dropped, malformed lines name file and line", "[run_data]") {
    TempDir tmp("run_data_truncated");
    const std::string dir = test::record_run(tmp / "run", 1);
    const std::string data = read_text(dir + "/data.csv");
    // a process killed while writing leaves part of a line
    write_text(dir + "/data.csv", data.substr(0, data.size() - 25));
    RunData run(dir);
    CHECK(run.rows() == 33);
    CHECK(run.truncated());
    CHECK(run.get("snake.com.z").values.size() == 33);

    // a broken line that is not the last one is an error
    std::string broken = data;
    const size_t line3 = broken.find('\n', broken.find('\n') + 1) + 1;
    broken.insert(line3 + 1, "x");
    write_text(dir + "/data.csv", broken);
    CHECK_THROWS_WITH(RunData(dir).get("snake.com.z"),
                      dir + "/data.csv:3: column 'time': number expected, got '0x.03'");
    write_text(dir + "/data.csv", data.substr(0, data.find('\n') + 1) + "0,1,2\n");
    CHECK_THROWS_WITH(RunData(dir).get("snake.com.z"),
                      dir + "/data.csv:2: 81 fields expected, got 3");
    write_text(dir + "/data.csv", "time,a\n");
    CHECK_THROWS_WITH(RunData(dir),
                      dir +
                          "/data.csv:1: 81 columns expected (time and the 80 series of "
                          "series.csv), got 2");
    write_text(dir + "/run.json", "{\"format\": \"gaitlab run\",\n \"status\": }");
    CHECK_THROWS_WITH(RunData(dir), dir + "/run.json:2: JSON value expected, got '}'");
    write_text(dir + "/run.json", "[1, 2]");
    CHECK_THROWS_WITH(RunData(dir),
                      dir +
                          "/run.json:1: not a gaitlab run description (an object with "
                          "\"format\": \"gaitlab run\" expected)");
}

TEST_CASE("a folder that is not a run says what it lacks", "[run_data]") {
    TempDir tmp("run_data_missing");
    CHECK_THROWS_AS(RunData(tmp / "nothing"), IoError);
    CHECK_THROWS_WITH(RunData(tmp / "nothing"), "no run folder at " + (tmp / "nothing"));
    write_text(tmp / "file.txt", "x");
    CHECK_THROWS_WITH(RunData(tmp / "file.txt"),
                      tmp / "file.txt" + " is not a run folder: it is not a folder");
    fs::create_directories(tmp / "half");
    write_text(tmp / "half/run.json", "{}");
    CHECK_THROWS_WITH(RunData(tmp / "half"),
                      tmp / "half" +
                          " is not a run folder: it has no series.csv and data.csv (a run "
                          "folder holds run.json, series.csv, data.csv, events.csv, log.txt "
                          "and config/)");
}

TEST_CASE("compare finds the first differing value", "[run_data]") {
    TempDir a("run_data_cmp_a"), b("run_data_cmp_b");
    const std::string ra = test::record_run(a / "run", 1), rb = test::record_run(b / "run", 1);
    Comparison same = compare(RunData(ra), RunData(rb));
    CHECK(same.identical);
    CHECK(same.rows == 34);
    CHECK(same.difference.empty());
    // one value changed in the last digit
    std::string text = read_text(rb + "/data.csv");
    const size_t row5 = [&] {
        size_t p = 0;
        for (int i = 0; i < 5; ++i)
            p = text.find('\n', p) + 1;
        return p;
    }();
    const size_t comma = text.find(',', row5);
    const size_t end = text.find(',', comma + 1);
    char& last = text[end - 1];
    last = last == '1' ? '2' : '1';
    write_text(rb + "/data.csv", text);
    Comparison diff = compare(RunData(ra), RunData(rb));
    CHECK_FALSE(diff.identical);
    CHECK_THAT(diff.difference,
               Catch::StartsWith("first difference at t = 0.12 s (data.csv line 6): snake.com.x "
                                 "is "));
}
