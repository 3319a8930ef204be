// gaitlab view RUN_FOLDER: a recorded run served to the pages. The scene is rebuilt from the
// run's script, the timeline plays the recorded poses back (seek, step, play), the routes under
// /api/run give the series, their data and CSV, the run folders a page may open; bad folders
// and bad requests get clear messages, and the folder on disk stays as it was.
#include "gaitlab/viewer/run_view.h"

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include <httplib.h>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli/run_gaitlab.h"

using namespace gaitlab;
using namespace gaitlab::viewer;
using gaitlab::test::read_text;
using gaitlab::test::run_gaitlab;
using gaitlab::test::TempDir;
using gaitlab::test::write_text;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// the bodies whose poses a run recorded
size_t posed_bodies(const RunData& run) {
    size_t n = 0;
    for (const SeriesInfo& s : run.series())
        n += s.body.empty() || s.value != "x" ? 0 : 1;
    return n;
}

std::string walk() {
    return std::string(GAITLAB_SOURCE_DIR) + "/tests/viewer/scripts/walk.lua";
}

// records walk.lua for `seconds` into DIR/NAME
std::string record_walk(const TempDir& dir, const std::string& name, const char* seconds = "1") {
    const auto r = run_gaitlab({"run", walk(), "--record", name, "--", seconds}, dir.str());
    REQUIRE(r.status == 0);
    return dir / name;
}

// serves a view on its own thread until the test ends
struct Serving {
    RunView& view;
    std::atomic<bool> stop{false};
    std::thread thread;
    explicit Serving(RunView& v) : view(v) {
        thread = std::thread([this] { view.serve([this] { return stop.load(); }); });
    }
    ~Serving() {
        stop = true;
        thread.join();
    }
};

struct Reply {
    int status = 0;
    std::string body;
    std::string disposition;
};

Reply get(int port, const std::string& path) {
    httplib::Client c("127.0.0.1", port);
    auto r = c.Get(path);
    if (!r) return {};
    return {r->status, r->body, r->get_header_value("Content-Disposition")};
}

Reply post(int port, const std::string& path, const std::string& body,
           const std::string& type = "application/json") {
    httplib::Client c("127.0.0.1", port);
    auto r = c.Post(path, body, type);
    if (!r) return {};
    return {r->status, r->body, ""};
}

// the latest frame, once `ok` says it is the one (at most 30 s: a loaded machine, a sanitizer)
template <class Ok>
json frame_where(RunView& view, Ok ok) {
    const int port = view.server().port();
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    json f;
    while (std::chrono::steady_clock::now() < end) {
        // the event stream's first frame is the latest one
        httplib::Client c("127.0.0.1", port);
        std::string got;
        c.Get("/api/events", [&](const char* data, size_t n) {
            got.append(data, n);
            return got.find("event: frame") == std::string::npos ||
                   got.find("\n\n", got.find("event: frame")) == std::string::npos;
        });
        const auto at = got.find("event: frame\ndata: ");
        if (at != std::string::npos) {
            const auto start = at + 19;
            f = json::parse(got.substr(start, got.find("\n\n", start) - start));
            if (ok(f)) return f;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    FAIL("no such frame within 30 s; the last one: " << f.dump().substr(0, 300));
    return f;
}

// the latest frame, once its time is `t`
json frame_at(RunView& view, double t) {
    return frame_where(view, [t](const json& f) { return f["time"].get<double>() == t; });
}

}  // namespace

TEST_CASE("gaitlab view serves a recorded run: its scene and series and their data and CSV") {
    TempDir dir("run_view");
    const std::string run = record_walk(dir, "walk");
    const RunData data(run);
    RunView view(run, {});
    CHECK(view.notes().empty());
    CHECK(view.duration() == data.times().back());  // the rows of 1 s: one per control period
    Serving serving(view);
    const int port = view.server().port();

    const Reply info = get(port, "/api/run");
    REQUIRE(info.status == 200);
    const json i = json::parse(info.body);
    CHECK(i["name"] == "walk");
    CHECK(i["state"] == "finished");
    CHECK(i["poses"] == true);
    CHECK(i["scene_rebuilt"] == true);
    CHECK(i["series"].size() == data.series().size());
    CHECK(i["rows"].get<long>() == data.rows());

    // the scene as the script made it: the snake's bodies, the ramp, stairs and boxes
    const json scene = json::parse(get(port, "/api/scene").body);
    CHECK(scene["bodies"].size() == posed_bodies(data));
    CHECK(scene["bodies"].size() > 5);
    CHECK(scene["objects"].size() >= 4);
    CHECK(scene["controllers"].empty());  // nothing to steer in a recording

    // data as RunData reads it, NaN-free here
    const Reply d = get(port, "/api/run/data?series=snake.com.x,snake.angle%5B2%5D");
    REQUIRE(d.status == 200);
    const json dj = json::parse(d.body);
    const SeriesData com = data.get("snake.com.x");
    CHECK(dj["time"].get<std::vector<double>>() == com.time);
    CHECK(dj["values"][0].get<std::vector<double>>() == com.values);
    CHECK(dj["values"][1].get<std::vector<double>>() == data.get("snake.angle[2]").values);

    // the CSV download is what `gaitlab data --csv` writes, byte for byte
    const Reply csv = get(port, "/api/run/csv?series=snake.com.x,snake.angle%5B2%5D");
    REQUIRE(csv.status == 200);
    CHECK(csv.disposition == "attachment; filename=\"walk.csv\"");
    data.write_csv(dir / "expected.csv", {"snake.com.x", "snake.angle[2]"});
    CHECK(csv.body == read_text(dir / "expected.csv"));
    CHECK(csv.body.rfind("time,snake.com.x,snake.angle[2]\n0,", 0) == 0);
}

TEST_CASE("gaitlab view: seek and step and play move the recorded bodies") {
    TempDir dir("run_view");
    const std::string run = record_walk(dir, "walk");
    const RunData data(run);
    RunView view(run, {});
    Serving serving(view);
    const int port = view.server().port();

    const json start = frame_at(view, 0);
    REQUIRE(start["time"] == 0);
    REQUIRE(post(port, "/api/command", R"({"command": "seek", "time": 0.6})").status == 200);
    const json f = frame_at(view, 0.6);
    REQUIRE(f["time"] == 0.6);
    // the tail's recorded position at the row of 0.6 s
    const std::vector<double> t = data.times();
    const auto row = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), 0.6) - t.begin() - 1);
    CHECK(f["poses"][0].get<double>() == Approx(data.get("snake.tail.x").values[row]).margin(1e-5));
    CHECK(f["poses"][1].get<double>() == Approx(data.get("snake.tail.y").values[row]).margin(1e-5));
    CHECK(f["poses"] != start["poses"]);
    CHECK(f["state"]["recorded"]["end"] == t.back());

    // a step goes to the next row; a seek past the end stops at the end
    REQUIRE(post(port, "/api/command", R"({"command": "step"})").status == 200);
    CHECK(frame_at(view, t[row + 1])["time"] == t[row + 1]);
    REQUIRE(post(port, "/api/command", R"({"command": "seek", "time": 99})").status == 200);
    CHECK(frame_at(view, t.back())["time"] == t.back());
    // play from the end starts again and plays to the end, as fast as asked
    REQUIRE(post(port, "/api/command", R"({"command": "speed", "value": 10})").status == 200);
    const auto frames = view.server().stats().frames;
    REQUIRE(post(port, "/api/command", R"({"command": "play"})").status == 200);
    const json playing = frame_where(view, [](const json& j) { return j["state"]["playing"]; });
    CHECK(playing["state"]["playing"] == true);
    CHECK(playing["time"].get<double>() < t.back());
    const json end = frame_where(view, [](const json& j) { return !j["state"]["playing"]; });
    CHECK(end["time"] == t.back());
    CHECK(end["state"]["playing"] == false);
    CHECK(view.server().stats().frames > frames + 3);  // frames on the way
}

TEST_CASE("gaitlab view: bad requests get a clear answer and change nothing") {
    TempDir dir("run_view");
    const std::string run = record_walk(dir, "walk");
    RunView view(run, {});
    Serving serving(view);
    const int port = view.server().port();

    Reply r = get(port, "/api/run/data");
    CHECK(r.status == 400);
    CHECK(r.body.find("parameter 'series' expected") != std::string::npos);
    r = get(port, "/api/run/data?series=snake.com.q");
    CHECK(r.status == 400);
    CHECK(r.body.find("snake.com.q") != std::string::npos);
    r = get(port, "/api/run/csv?series=nothing.here");
    CHECK(r.status == 400);
    r = get(port, "/api/run/data?series=snake.com.x&from=soon");
    CHECK(r.status == 400);
    CHECK(r.body.find("parameter 'from': a time in s expected (got 'soon')") != std::string::npos);
    r = get(port, "/api/run/nothing");
    CHECK(r.status == 404);
    // opening a folder the list does not offer, whatever the path
    for (const char* path : {"/etc", "../walk", "/", "walk/config"}) {
        r = post(port, "/api/run/open", json{{"path", path}}.dump());
        INFO(path);
        CHECK(r.status == 400);
        CHECK(r.body.find("is not a run folder the list offers") != std::string::npos);
    }
    r = post(port, "/api/run/open", "{not json");
    CHECK(r.status == 400);
    r = post(port, "/api/run/open", "path=/etc", "application/x-www-form-urlencoded");
    CHECK(r.status == 415);
    // no video is being made
    r = post(port, "/api/run/video?offset=0", "xx", "application/octet-stream");
    CHECK(r.status == 404);
    // seek needs a time
    r = post(port, "/api/command", R"({"command": "seek"})");
    CHECK(r.status == 400);
    CHECK(r.body.find("field 'time'") != std::string::npos);
    r = post(port, "/api/command", R"({"command": "seek", "time": "x", "when": 1})");
    CHECK(r.status == 400);
    CHECK(json::parse(get(port, "/api/run").body)["name"] == "walk");
}

TEST_CASE("a live view refuses seek: only a recorded run has a timeline") {
    Server server({});
    httplib::Client c("127.0.0.1", server.port());
    auto r = c.Post("/api/command", R"({"command": "seek", "time": 1})", "application/json");
    REQUIRE(r);
    CHECK(r->status == 400);
    CHECK(r->body.find("only a recorded run has a timeline") != std::string::npos);
    auto g = c.Get("/api/run");
    REQUIRE(g);
    CHECK(g->body == R"({"recorded":false})");
    g = c.Get("/api/run/data?series=x");
    REQUIRE(g);
    CHECK(g->status == 404);
}

TEST_CASE("gaitlab view: the picker lists the run's neighbours and opens one") {
    TempDir dir("run_view");
    const std::string a = record_walk(dir, "first");
    record_walk(dir, "second", "0.5");
    fs::create_directories(dir / "not-a-run");
    RunView view(a, {});
    Serving serving(view);
    const int port = view.server().port();
    const json list = json::parse(get(port, "/api/run/list").body);
    std::vector<std::string> runs = list["runs"];
    const std::string second = (fs::path(dir.str()) / "second").lexically_normal().string();
    CHECK(std::find(runs.begin(), runs.end(), second) != runs.end());
    for (const std::string& r : runs)
        CHECK(r.find("not-a-run") == std::string::npos);
    const Reply r = post(port, "/api/run/open", json{{"path", second}}.dump());
    INFO(list.dump() << " " << r.body);
    REQUIRE(r.status == 200);
    CHECK(json::parse(get(port, "/api/run").body)["name"] == "second");
    const double end = RunData(second).times().back();
    const json f =
        frame_where(view, [end](const json& j) { return j["state"]["recorded"]["end"] == end; });
    CHECK(f["state"]["recorded"]["end"] == end);
    CHECK(f["time"] == 0);
}

TEST_CASE("gaitlab view: bad run folders name the file and what is wrong and stay as they are") {
    TempDir dir("run_view");
    const std::string run = record_walk(dir, "walk");

    // not a run folder
    fs::create_directories(dir / "empty");
    CHECK_THROWS_WITH(RunView(dir / "empty", {}), Catch::Contains("run.json"));
    CHECK_THROWS_WITH(RunView(dir / "nowhere", {}), Catch::Contains("nowhere"));

    // a corrupt line in data.csv: its file and line
    fs::copy(run, dir / "corrupt", fs::copy_options::recursive);
    std::string csv = read_text(dir / "corrupt/data.csv");
    const auto line3 = csv.find('\n', csv.find('\n') + 1) + 1;
    csv.replace(line3, csv.find(',', line3) - line3, "zero");
    write_text(dir / "corrupt/data.csv", csv);
    const std::string before = read_text(dir / "corrupt/data.csv");
    CHECK_THROWS_WITH(RunView(dir / "corrupt", {}), Catch::Contains("data.csv:3"));
    CHECK(read_text(dir / "corrupt/data.csv") == before);

    // a missing run.json
    fs::copy(run, dir / "nometa", fs::copy_options::recursive);
    fs::remove(dir / "nometa/run.json");
    CHECK_THROWS_WITH(RunView(dir / "nometa", {}), Catch::Contains("run.json"));

    // a broken run.json: its file and line
    fs::copy(run, dir / "badmeta", fs::copy_options::recursive);
    write_text(dir / "badmeta/run.json", "{\n  \"format\": \"gaitlab run\",\n  oops\n}\n");
    CHECK_THROWS_WITH(RunView(dir / "badmeta", {}), Catch::Contains("run.json:3"));

    // a series file cut short (a killed run): the last line is left out, and said
    fs::copy(run, dir / "cut", fs::copy_options::recursive);
    std::string cut = read_text(dir / "cut/data.csv");
    cut.resize(cut.size() - 7);
    write_text(dir / "cut/data.csv", cut);
    RunView view(dir / "cut", {});
    REQUIRE(view.notes().size() == 1);
    CHECK(view.notes()[0].find("cut short") != std::string::npos);
    CHECK(read_text(dir / "cut/data.csv") == cut);
}

TEST_CASE("gaitlab view: runs without poses or without a script still play what they have") {
    TempDir dir("run_view");
    write_text(dir / "com.lua", R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
local sim = gaitlab.simulation{ world = world, record = { dir = "com", series = { "snake.com.*" } } }
sim:run(0.3)
)");
    REQUIRE(run_gaitlab({"run", "com.lua"}, dir.str()).status == 0);
    {
        RunView view(dir / "com", {});
        REQUIRE(view.notes().size() == 1);
        CHECK(view.notes()[0].find("recorded no body poses") != std::string::npos);
        Serving serving(view);
        // the robot stands where the script put it; the timeline still runs
        const json scene = json::parse(get(view.server().port(), "/api/scene").body);
        CHECK(scene["bodies"].size() >= 3);
        REQUIRE(
            post(view.server().port(), "/api/command", R"({"command":"seek","time":0.2})").status ==
            200);
        const json f = frame_at(view, 0.2);
        CHECK(f["time"] == 0.2);
        CHECK(f["poses"].size() == scene["bodies"].size() * 7);
    }

    // its script gone: the bodies of the pose series, as small boxes
    const std::string run = record_walk(dir, "walk");
    fs::remove(dir / "walk/config/walk.lua");
    RunView view(run, {});
    REQUIRE(view.notes().size() == 1);
    CHECK(view.notes()[0].find("the scene could not be rebuilt") != std::string::npos);
    CHECK(view.notes()[0].find("walk.lua is missing") != std::string::npos);
    Serving serving(view);
    const json scene = json::parse(get(view.server().port(), "/api/scene").body);
    CHECK(scene["bodies"].size() == posed_bodies(RunData(run)));
    CHECK(scene["objects"].empty());
    REQUIRE(post(view.server().port(), "/api/command", R"({"command":"seek","time":0.6})").status ==
            200);
    const json f = frame_at(view, 0.6);
    CHECK(f["poses"][0].get<double>() != 0);  // the recorded tail, not the origin
}

TEST_CASE("gaitlab view from the command line: bad folders and options and no chromium") {
    TempDir dir("run_view");
    auto r = run_gaitlab({"view", "nowhere"}, dir.str());
    CHECK(r.status == 1);
    CHECK(r.err.find("gaitlab: ") == 0);
    CHECK(r.err.find("nowhere") != std::string::npos);
    r = run_gaitlab({"view"}, dir.str());
    CHECK(r.status == 2);
    r = run_gaitlab({"view", "x", "--port", "abc"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err.find("--port: a port number from 1 to 65535 expected") != std::string::npos);
    r = run_gaitlab({"view", "x", "--speed", "2"}, dir.str());
    CHECK(r.status == 2);  // --speed is for --video
    record_walk(dir, "walk", "0.2");
    r = run_gaitlab({"view", "walk", "--video", "out.webm", "--speed", "0"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err.find("--speed: a real-time factor in (0, 100] expected") != std::string::npos);
    // not a number at all: still the factor's words (it said "a number of seconds expected")
    r = run_gaitlab({"view", "walk", "--video", "out.webm", "--speed", "nan"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err.find("--speed: a real-time factor in (0, 100] expected (got 'nan')") !=
          std::string::npos);
    r = run_gaitlab({"view", "walk", "--video", "out.webm", "--size", "big"}, dir.str());
    CHECK(r.status == 2);
    CHECK(r.err.find("--size: WIDTHxHEIGHT in pixels expected") != std::string::npos);
    // no chromium: how to install it, and no file
    ::setenv("GAITLAB_CHROMIUM", (dir / "no-chromium").c_str(), 1);
    r = run_gaitlab({"view", "walk", "--video", "out.webm"}, dir.str());
    ::unsetenv("GAITLAB_CHROMIUM");
    CHECK(r.status == 1);
    CHECK(r.err.find("--video needs chromium, which is not installed: install it with 'sudo apt "
                     "install chromium'") != std::string::npos);
    CHECK(!fs::exists(dir / "out.webm"));
    CHECK(!fs::exists(dir / "out.webm.part"));
}

TEST_CASE("gaitlab view: a script that never steps is stopped and the run still opens") {
    TempDir dir("run_view");
    const std::string run = record_walk(dir, "walk", "0.2");
    // the run folder's copy of the script now loops before it makes its simulation
    write_text(dir / "walk/config/walk.lua", "while true do end\n");
    const RunData data(run);
    const auto start = std::chrono::steady_clock::now();
    const RecordedScene slow = rebuild_scene(data, 0.5);
    CHECK(slow.problem == "its script did not step simulation 1 within 0.5 s");
    const RecordedScene cancelled = rebuild_scene(data, 30, [] { return true; });
    CHECK(cancelled.problem == "interrupted");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
    // the view opens with the bodies of the pose series
    RunViewOptions options;
    options.rebuild_seconds = 0.5;
    RunView view(run, {}, options);
    REQUIRE(view.notes().size() == 1);
    CHECK(view.notes()[0].find("did not step simulation 1 within 0.5 s") != std::string::npos);
}

TEST_CASE("gaitlab view plays the moving objects back at their recorded poses") {
    TempDir dir("run_view");
    // a box dropped from 0.3 m falls to the floor; a static box and a rolling cylinder
    write_text(dir / "drop.lua", R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
local world = gaitlab.world{}
world:box{ size = { 0.1, 0.1, 0.1 }, position = { 1, 1, 0.05 } }
world:box{ size = { 0.1, 0.1, 0.1 }, position = { 0.5, 0.5, 0.3 }, mass = 0.1 }
world:cylinder{ radius = 0.05, length = 0.1, position = { -0.5, 0.5, 0.4 }, mass = 0.1 }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
local series = arg[1] == "old" and { "robot", "controller" } or nil
local sim = gaitlab.simulation{ world = world, record = { dir = arg[1], series = series } }
sim:run(1)
)");
    REQUIRE(run_gaitlab({"run", "drop.lua", "--", "drop"}, dir.str()).status == 0);
    const RunData data(dir / "drop");
    // the recording has the moving objects' poses: box 2 (box 1 is static) and cylinder 1
    const std::vector<SeriesInfo>& series = data.series();
    auto has = [&series](const std::string& name) {
        for (const SeriesInfo& s : series)
            if (s.name == name) return s.kind == SeriesKind::object;
        return false;
    };
    CHECK(has("box_2.x"));
    CHECK(has("box_2.qz"));
    CHECK(has("cylinder_1.z"));
    CHECK_FALSE(has("box_1.x"));
    {
        RunView view(dir / "drop", {});
        CHECK(view.notes().empty());
        Serving serving(view);
        const int port = view.server().port();
        const json scene = json::parse(get(port, "/api/scene").body);
        const std::size_t bodies = scene["bodies"].size();
        REQUIRE(scene["dynamic"] == 2);
        const std::vector<double> t = data.times();
        const std::vector<double> z = data.get("box_2.z").values;
        const std::vector<double> cz = data.get("cylinder_1.z").values;
        const json start = frame_at(view, 0);
        REQUIRE(start["poses"].size() == (bodies + 2) * 7);
        CHECK(start["poses"][bodies * 7 + 2].get<double>() == Approx(z[0]).margin(1e-9));
        CHECK(z[0] > 0.25);
        REQUIRE(post(port, "/api/command", R"({"command": "seek", "time": 0.9})").status == 200);
        const json f = frame_at(view, 0.9);
        const auto row =
            static_cast<size_t>(std::upper_bound(t.begin(), t.end(), 0.9) - t.begin() - 1);
        // on the floor now, as recorded: the box and the cylinder both fell
        CHECK(z[row] == Approx(0.05).margin(0.005));
        // a frame carries positions to 5 decimals (10 µm; server.cpp, encode_frame), and on the
        // compliant floor the two rest a few µm low
        const double frame_digits = 0.5e-5 + 1e-12;
        CHECK(f["poses"][bodies * 7 + 2].get<double>() == Approx(z[row]).margin(frame_digits));
        CHECK(f["poses"][(bodies + 1) * 7 + 2].get<double>() ==
              Approx(cz[row]).margin(frame_digits));
        CHECK(cz[row] < 0.3);
        CHECK(f["poses"][(bodies + 1) * 7 + 0].get<double>() ==
              Approx(data.get("cylinder_1.x").values[row]).margin(frame_digits));
    }

    // a recording without them (as folders from before gaitlab recorded them): they stay where
    // the script put them, and the view says so
    REQUIRE(run_gaitlab({"run", "drop.lua", "--", "old"}, dir.str()).status == 0);
    RunView view(dir / "old", {});
    REQUIRE(view.notes().size() == 1);
    CHECK(view.notes()[0] ==
          "2 of the world's 2 moving objects have no recorded pose (box 2, cylinder 1; series "
          "OBJECT.x ... qz, recorded since gaitlab records them): they stay where the script put "
          "them");
    Serving serving(view);
    const int port = view.server().port();
    const std::size_t bodies = json::parse(get(port, "/api/scene").body)["bodies"].size();
    REQUIRE(post(port, "/api/command", R"({"command": "seek", "time": 0.9})").status == 200);
    const json f = frame_at(view, 0.9);
    CHECK(f["poses"][bodies * 7 + 2].get<double>() == Approx(0.3).margin(1e-9));
    CHECK(f["poses"][bodies * 7 + 0].get<double>() == Approx(0.5).margin(1e-9));
}
