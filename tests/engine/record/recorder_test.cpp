// The recorder (engine/src/record/recorder.cpp): run folder contents, rows every record_every
// ticks, numbers that read back bit for bit, events, flushing, and write failures.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "engine/sim_support.h"
#include "gaitlab/controllers/hopf.h"
#include "gaitlab/error.h"
#include "gaitlab/recorder.h"
#include "gaitlab/run_data.h"
#include "gaitlab/version.h"
#include "temp_dir.h"

using namespace gaitlab;
using gaitlab::test::read_text;
using gaitlab::test::TempDir;
namespace fs = std::filesystem;

namespace {

// While it lives, files of this process stop growing at `limit` bytes, as on a full disk
// (RLIMIT_FSIZE, with SIGXFSZ ignored: the write fails with EFBIG instead of killing the
// process); 0 leaves the limit as it is, for a test to set later (FillsDisk)
class DiskLimit {
  public:
    explicit DiskLimit(rlim_t limit = 0) {
        REQUIRE(getrlimit(RLIMIT_FSIZE, &old_) == 0);
        previous_ = std::signal(SIGXFSZ, SIG_IGN);
        if (limit == 0) return;
        rlimit small = old_;
        small.rlim_cur = limit;
        REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
    }
    ~DiskLimit() {
        setrlimit(RLIMIT_FSIZE, &old_);
        std::signal(SIGXFSZ, previous_);
    }
    DiskLimit(const DiskLimit&) = delete;
    DiskLimit& operator=(const DiskLimit&) = delete;

  private:
    rlimit old_{};
    void (*previous_)(int) = nullptr;
};

// lines of a text file
std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

Simulation snake_sim(int modules = 4) {
    return Simulation(test::chain_world(modules, Connection::pitch_pitch));
}

}  // namespace

TEST_CASE("a run folder holds the data, the series list, events, log and configuration",
          "[recorder]") {
    TempDir tmp("recorder_folder");
    Simulation sim(test::chain_world(4, Connection::pitch_pitch));
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = tmp / "run";
    RunContext ctx;
    ctx.script = "snake.lua";
    ctx.args = {"a", "b"};
    ctx.script_seed = 7;
    ctx.files.push_back({"script", "snake.lua", "/somewhere/snake.lua", "print(1)\n", "", 0, ""});
    ctx.files.push_back({"controller", "controllers/c.lua", "/somewhere/controllers/c.lua",
                         "return 1\n", "", 0, ""});
    {
        Recorder rec(sim, o, ctx);
        sim.run(0.3);
        rec.close();
        CHECK(rec.rows() == 11);  // t = 0 and every 30 ticks up to 300
    }
    for (const char* f : {"run.json", "series.csv", "data.csv", "events.csv", "log.txt"})
        CHECK(fs::exists(tmp / ("run/" + std::string(f))));
    CHECK(read_text(tmp / "run/config/snake.lua") == "print(1)\n");
    CHECK(read_text(tmp / "run/config/controllers/c.lua") == "return 1\n");

    const auto data = lines(read_text(tmp / "run/data.csv"));
    REQUIRE(data.size() == 12);
    CHECK(data[0].rfind("time,snake.com.x,snake.com.y,snake.com.z,snake.com.vx,", 0) == 0);
    CHECK(data[1].rfind("0,", 0) == 0);
    CHECK(data[2].rfind("0.03,", 0) == 0);
    CHECK(data[11].rfind("0.3,", 0) == 0);

    RunData run(tmp / "run");
    CHECK(run.meta().status == "finished");
    CHECK(run.meta().script == "snake.lua");
    CHECK(run.meta().args == std::vector<std::string>{"a", "b"});
    CHECK(run.meta().script_seed == 7);
    CHECK(run.meta().record_every == 30);
    CHECK(run.meta().first_tick == 0);
    CHECK(run.meta().last_tick == 300);
    CHECK(run.meta().options.control_every == 30);
    REQUIRE(run.meta().files.size() == 2);
    CHECK(run.meta().files[1].role == "controller");
    CHECK(run.meta().files[1].path == "controllers/c.lua");
    // each file's FNV-1a 64 hash (the values computed independently of gaitlab)
    CHECK(run.meta().files[0].hash == "fnv1a64:c36adf2b03cacd3c");
    CHECK(run.meta().files[1].hash == "fnv1a64:2190e8ea4e8cab5a");
    std::string cpu, compiler, commit;
    std::vector<std::string> keys;
    for (const auto& [k, v] : run.meta().provenance) {
        keys.push_back(k);
        if (k == "cpu") cpu = v;
        if (k == "compiler") compiler = v;
        if (k == "commit") commit = v;
    }
    CHECK_FALSE(cpu.empty());
    CHECK_FALSE(compiler.empty());
    // the commit this very test was built from ("unknown" only outside a git work tree)
    CHECK(commit == source_commit());
    CHECK_FALSE(commit.empty());
    if (fs::exists(fs::path(GAITLAB_SOURCE_DIR) / ".git")) CHECK(commit != "unknown");
    // provenance reads back in the order run.json has it
    REQUIRE(keys.size() >= 3);
    CHECK(keys[0] == "gaitlab");
    CHECK(keys[1] == "commit");
    CHECK(keys[2] == "bullet");
    CHECK(run.rows() == 11);
    CHECK_FALSE(run.truncated());
    CHECK_THAT(run.log(),
               Catch::StartsWith("recording 80 series every 30 ticks from t = 0 s into "));
    CHECK_THAT(run.log(), Catch::EndsWith("recording finished at t = 0.3 s: 11 rows\n"));
}

TEST_CASE("recorded numbers read back bit for bit", "[recorder]") {
    TempDir tmp("recorder_bits");
    Simulation sim = snake_sim(6);
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = tmp / "run";
    o.record_every = 7;
    std::vector<std::vector<double>> expected;
    {
        Recorder rec(sim, o);
        // what the recorder samples, sampled again alongside it
        SeriesSet probe(sim, {});
        std::vector<double> row(probe.size());
        probe.sample(sim, row.data());
        expected.push_back(row);
        sim.add_observer([&](const Simulation& s) {
            probe.tick(s);
            if (s.ticks() % 7 == 0) {
                probe.sample(s, row.data());
                expected.push_back(row);
            }
        });
        sim.run(1.0);
    }
    RunData run(tmp / "run");
    REQUIRE(run.rows() == static_cast<long>(expected.size()));
    const std::vector<std::string> names = run.names();
    const auto all = run.get(names);
    for (size_t k = 0; k < names.size(); ++k) {
        for (size_t i = 0; i < expected.size(); ++i) {
            const double want = expected[i][k], got = all[k].values[i];
            INFO(names[k] << " row " << i);
            REQUIRE(std::memcmp(&want, &got, sizeof want) == 0);
        }
    }
    // the energy integrates |torque * velocity| every tick: it grows and is positive
    const SeriesData e = run.get("snake.energy");
    CHECK(e.values.front() == 0);
    CHECK(e.values.back() > 0);
    for (size_t i = 1; i < e.values.size(); ++i)
        CHECK(e.values[i] >= e.values[i - 1]);
    CHECK(e.time[1] == Approx(0.007));
}

TEST_CASE("parameter changes and resets are events with their tick and origin", "[recorder]") {
    TempDir tmp("recorder_events");
    Simulation sim = snake_sim();
    auto ctl = test::sine(30, 0.5, 120);
    test::drive(sim, "pitch", ctl);
    RecordOptions o;
    o.dir = tmp / "run";
    {
        Recorder rec(sim, o);
        sim.run(0.1);
        ctl->set_param("amplitude", 35);
        ctl->set_param("amplitude", 35);  // no change, no event
        sim.add_pre_tick([&](Simulation& s) {
            if (s.ticks() == 150) s.controller(0).set_param("frequency", 1, Origin::viewer);
        });
        sim.run(0.1);
        sim.reset(Origin::console);
        sim.run(0.06);
    }
    RunData run(tmp / "run");
    const std::vector<Event> ev = run.events();
    REQUIRE(ev.size() == 3);
    CHECK(ev[0].tick == 100);
    CHECK(ev[0].kind == EventKind::param);
    CHECK(ev[0].origin == Origin::script);
    CHECK(ev[0].name == "sine.amplitude");
    CHECK(ev[0].value == 35);
    CHECK(ev[1].tick == 150);
    CHECK(ev[1].origin == Origin::viewer);
    CHECK(ev[1].name == "sine.frequency");
    CHECK(ev[2].kind == EventKind::reset);
    CHECK(ev[2].origin == Origin::console);
    CHECK(ev[2].tick == 200);  // when it happened
    // after the reset the rows start again at t = 0, with the state the reset made
    const SeriesData a = run.get("sine.amplitude");
    const SeriesData x = run.get("snake.com.x");
    REQUIRE(a.time.size() == 7 + 1 + 2);
    CHECK(a.time[7] == 0);
    CHECK(a.values[7] == 35);  // parameters survive a reset
    CHECK(x.values[7] == x.values[0]);
}

TEST_CASE("a run folder must be new, empty or an earlier run", "[recorder]") {
    TempDir tmp("recorder_dirs");
    Simulation sim = snake_sim(2);
    RecordOptions o;
    o.dir = tmp / "run";
    { Recorder rec(sim, o); }
    test::write_text(tmp / "run/extra.txt", "kept");
    { Recorder again(sim, o); }  // an earlier run is replaced
    CHECK(read_text(tmp / "run/extra.txt") == "kept");
    CHECK(RunData(tmp / "run").rows() == 1);

    fs::create_directories(tmp / "other");
    test::write_text(tmp / "other/notes.txt", "mine");
    o.dir = tmp / "other";
    CHECK_THROWS_WITH(Recorder(sim, o),
                      "cannot record into " + (tmp / "other") +
                          ": the folder is not empty and holds no earlier run (record into a "
                          "new or empty folder)");
    // under a regular file (root ignores permission bits, not this)
    o.dir = tmp / "other/notes.txt/run";
    CHECK_THROWS_WITH(Recorder(sim, o),
                      Catch::StartsWith("cannot create run folder " + o.dir + ": Not a directory"));
    o.dir = tmp / "run";
    o.record_every = -1;
    CHECK_THROWS_WITH(Recorder(sim, o), "record_every must be at least 1 (got -1)");
    o.record_every = 1;
    o.flush_seconds = -2;
    CHECK_THROWS_WITH(Recorder(sim, o),
                      "flush_seconds must be a non-negative number of seconds (got -2)");
}

TEST_CASE("a write failure stops the run with a clear message and keeps what was written",
          "[recorder]") {
    TempDir tmp("recorder_full");
    Simulation sim = snake_sim(4);
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = tmp / "run";
    o.flush_seconds = 0;
    Recorder rec(sim, o);
    sim.run(0.3);
    // the disk is "full" about 20 kB further on
    const auto size = static_cast<rlim_t>(fs::file_size(tmp / "run/data.csv"));
    std::string message;
    try {
        const DiskLimit full(size + 20000);
        sim.run(60);
    } catch (const IoError& e) {
        message = e.what();
    }
    CHECK(message == "cannot write " + (tmp / "run/data.csv") +
                         ": File too large (recording stopped; what was written before is kept)");
    CHECK(sim.time() < 10);  // it stopped the run
    CHECK(rec.closed());
    RunData run(tmp / "run");
    CHECK(run.rows() >= 11);
    CHECK(run.meta().status == "failed");
    CHECK_THAT(run.meta().message, Catch::Contains("File too large"));
    CHECK_THAT(run.log(), Catch::Contains("recording stopped at t = "));
    rec.close();  // nothing more to do, no second error
    // run.json says the recording stopped there: the data ends before the run did, so the
    // same run recorded to its end is identical up to the last row (what a replay checks)
    CHECK(run.meta().recording_failed);
    Simulation again = snake_sim(4);
    test::drive(again, "pitch", test::sine(40, 0.5, 120));
    o.dir = tmp / "whole";
    {
        Recorder whole(again, o);
        again.run(sim.time());
    }
    CHECK_FALSE(RunData(o.dir).meta().recording_failed);
    const Comparison c = compare(run, RunData(o.dir));
    INFO(c.difference);
    CHECK(c.identical);
    CHECK(c.rows == run.rows());
}

namespace {

// the whole number run.json gives `key` ("rows": 12); -1 if it has none
long meta_number(const std::string& meta, const std::string& key) {
    const size_t at = meta.find("\"" + key + "\": ");
    if (at == std::string::npos) return -1;
    return std::stol(meta.substr(at + key.size() + 4));
}

}  // namespace

TEST_CASE("after a failed write run.json counts the rows data.csv holds, not those dropped",
          "[recorder]") {
    // the failed write is the recorder's own (its buffer full) or one that sim:flush() asks for
    const bool asked = GENERATE(false, true);
    CAPTURE(asked);
    TempDir tmp("recorder_counts");
    Simulation sim = snake_sim(4);
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = tmp / "run";
    o.record_every = 1;
    o.flush_seconds = 1e6;  // no flush by the clock: the buffer holds hundreds of rows
    Recorder rec(sim, o);
    if (asked) sim.run(0.2);
    // the disk is "full" 100 kB on: the write of the buffer stops part way through its rows
    const auto size = static_cast<rlim_t>(fs::file_size(tmp / "run/data.csv"));
    std::string message;
    try {
        const DiskLimit full(size + 100000);
        if (asked) {
            rec.flush();
        } else {
            sim.run(60);
        }
    } catch (const IoError& e) {
        message = e.what();
    }
    CHECK_THAT(message, Catch::Contains("File too large (recording stopped; what was written "
                                        "before is kept)"));
    CHECK(rec.closed());
    if (asked) {
        sim.run(0.1);  // nothing more is written
    }
    RunData run(tmp / "run");
    const std::vector<double> t = run.times();
    REQUIRE(!t.empty());
    // rows were dropped: some never reached the file, one of them only in part
    CHECK(run.rows() > 10);
    CHECK(rec.rows() > run.rows() + 10);
    CHECK(fs::file_size(tmp / "run/data.csv") == size + 100000);
    CHECK(run.meta().status == "failed");
    CHECK(run.meta().recording_failed);
    // run.json counts what data.csv holds: its rows, and the tick of the last of them
    const std::string meta = read_text(tmp / "run/run.json");
    CHECK(meta_number(meta, "rows") == run.rows());
    CHECK(meta_number(meta, "first_tick") == 0);
    CHECK(run.meta().last_tick == std::lround(t.back() / sim.options().dt));
    CHECK(run.meta().last_tick == run.rows() - 1);
    CHECK(run.meta().last_tick < sim.ticks());
}

namespace {

// a controller of one value that, once armed, makes the disk "full" at `limit` bytes a file
// the next time its values are read: a recorder reads them for its first row, after run.json
// and series.csv and just before its first write of data.csv
class FillsDisk final : public Controller {
  public:
    FillsDisk() : Controller(ControllerDef{"fills", {}, {"level"}}) {}
    void step(ControlIO&) override {}
    rlim_t limit = 0;  // 0: not armed

  protected:
    void sync_values() const override {
        if (limit == 0) return;
        rlimit small{};
        getrlimit(RLIMIT_FSIZE, &small);
        small.rlim_cur = limit;
        setrlimit(RLIMIT_FSIZE, &small);
    }
};

}  // namespace

TEST_CASE("a write that fails as the recording starts marks run.json recording_failed",
          "[recorder]") {
    TempDir tmp("recorder_first_write");
    Simulation sim = snake_sim(12);
    auto fills = std::make_shared<FillsDisk>();
    test::drive(sim, "all", fills);
    RecordOptions o;
    o.flush_seconds = 1e6;  // only the constructor writes data.csv: its header and first row
    // what the first write of data.csv holds, and run.json beside it
    o.dir = tmp / "whole";
    {
        Recorder whole(sim, o);
        REQUIRE(fs::file_size(tmp / "whole/run.json") + 1000 <
                fs::file_size(tmp / "whole/data.csv"));
    }
    const auto first = static_cast<rlim_t>(fs::file_size(tmp / "whole/data.csv"));
    o.dir = tmp / "run";
    std::string message;
    try {
        const DiskLimit full;       // the controller sets it
        fills->limit = first - 10;  // the first row does not fit: run.json does
        Recorder rec(sim, o);
    } catch (const IoError& e) {
        message = e.what();
    }
    fills->limit = 0;
    CHECK(message == "cannot write " + (tmp / "run/data.csv") + ": File too large");
    CHECK(fs::file_size(tmp / "run/data.csv") == first - 10);
    // as for any failed write: the recording failed, and its data ends before its first row
    RunData run(tmp / "run");
    CHECK(run.meta().status == "failed");
    CHECK(run.meta().message == message);
    CHECK(run.meta().recording_failed);
    CHECK(run.rows() == 0);
    const std::string meta = read_text(tmp / "run/run.json");
    CHECK(meta_number(meta, "rows") == 0);
    CHECK(run.meta().last_tick == 0);
}

TEST_CASE("a run folder moved or deleted while recording stops the recording at once",
          "[recorder]") {
    TempDir tmp("recorder_moved");
    const bool deleted = GENERATE(false, true);
    CAPTURE(deleted);
    Simulation sim = snake_sim(4);
    test::drive(sim, "pitch", test::sine(40, 0.5, 120));
    RecordOptions o;
    o.dir = tmp / "run";
    o.flush_seconds = 0;
    Recorder rec(sim, o);
    sim.run(0.3);
    if (deleted) {
        fs::remove_all(o.dir);
    } else {
        fs::rename(o.dir, tmp / "moved");
    }
    fs::create_directories(o.dir);  // another folder of that name, as `mv run moved; mkdir run`
    std::string message;
    try {
        sim.run(60);
    } catch (const IoError& e) {
        message = e.what();
    }
    CHECK(sim.time() < 0.5);  // at the next flush, not when the run ends
    CHECK(rec.closed());
    if (deleted) {
        CHECK(message == "the run folder " + o.dir +
                             " was deleted while recording: nothing of this run is kept "
                             "(recording stopped)");
    } else {
        CHECK_THAT(message, Catch::StartsWith("the run folder " + o.dir +
                                              " was moved or replaced while recording"));
        // what was written went with the folder, an incomplete run up to its last row
        const RunData moved(tmp / "moved");
        CHECK(moved.rows() >= 10);
        CHECK(moved.meta().status == "running");
    }
    // nothing was written into the new folder of that name
    CHECK(fs::is_empty(o.dir));
    rec.close();  // nothing more to do, no second error
}

TEST_CASE("two recorders never share a folder: the second is refused, the first goes on",
          "[recorder]") {
    TempDir tmp("recorder_two");
    Simulation a = snake_sim(2), b = snake_sim(3);
    RecordOptions o;
    o.dir = tmp / "run";
    o.flush_seconds = 0;
    auto first = std::make_unique<Recorder>(a, o);
    a.run(0.3);
    const std::string pid = std::to_string(getpid());
    CHECK_THROWS_WITH(Recorder(b, o), "cannot record into " + o.dir +
                                          ": another recording is writing into it (process " + pid +
                                          "); record into another folder");
    a.run(0.3);
    first->close();
    // nothing of the first was lost
    const RunData run(o.dir);
    CHECK(run.rows() == 21);
    CHECK(run.series()[0].name == "snake.com.x");
    CHECK(run.meta().process.pid == getpid());
    // once it is closed, the folder is an earlier run: replaced
    { Recorder again(b, o); }
    CHECK(RunData(o.dir).rows() == 1);
    // a recorder that failed to start (here: config/a is a folder and a file) leaves the
    // folder to others
    RunContext clash;
    clash.files.push_back({"script", "a/b.lua", "/x/a/b.lua", "1", "", 0, ""});
    clash.files.push_back({"input", "a", "/x/a", "2", "", 0, ""});
    CHECK_THROWS_AS(Recorder(b, o, clash), IoError);
    { Recorder third(b, o); }
    CHECK(RunData(o.dir).rows() == 1);
}

TEST_CASE("a folder whose run.json names a process still writing it is refused", "[recorder]") {
    // a file system without locks still has run.json: it names this very process here
    TempDir tmp("recorder_alive");
    Simulation sim = snake_sim(2);
    RecordOptions o;
    o.dir = tmp / "run";
    { Recorder rec(sim, o); }
    std::string meta = read_text(tmp / "run/run.json");
    meta.replace(meta.find("\"status\": \"finished\""), 20, "\"status\": \"running\"");
    test::write_text(tmp / "run/run.json", meta);
    CHECK_THROWS_WITH(Recorder(sim, o), Catch::StartsWith("cannot record into " + o.dir +
                                                          ": another recording is writing "
                                                          "into it (process "));
    CHECK(fs::exists(tmp / "run/data.csv"));
}

TEST_CASE("a folder that may still be recording on another host is refused, not replaced",
          "[recorder]") {
    // a shared file system: run.json names a process of another host, which cannot be checked
    TempDir tmp("recorder_elsewhere");
    Simulation sim = snake_sim(2);
    RecordOptions o;
    o.dir = tmp / "run";
    o.flush_seconds = 0;
    {
        Recorder rec(sim, o);
        sim.run(0.3);
    }
    const long rows = RunData(o.dir).rows();
    std::string meta = read_text(tmp / "run/run.json");
    const std::string host = "\"host\": \"" + this_process().host + "\"";
    meta.replace(meta.find("\"status\": \"finished\""), 20, "\"status\": \"running\"");
    meta.replace(meta.find(host), host.size(), "\"host\": \"cluster-node-7\"");
    test::write_text(tmp / "run/run.json", meta);
    const std::string pid = std::to_string(getpid());
    CHECK_THROWS_WITH(Recorder(sim, o),
                      "cannot record into " + o.dir +
                          ": another recording may be writing into it on cluster-node-7 "
                          "(process " +
                          pid +
                          "), which cannot be checked from here; if that run has ended, "
                          "remove the folder, or record into another folder");
    CHECK(RunData(o.dir).rows() == rows);  // nothing of it was lost
    // an older run.json that names no process cannot be checked either
    const size_t at = meta.find("\"process\"");
    meta.erase(at, meta.find('}', at) + 2 - at);
    test::write_text(tmp / "run/run.json", meta);
    REQUIRE(RunData::read_meta(tmp / "run/run.json").process.pid == 0);
    CHECK_THROWS_WITH(Recorder(sim, o), Catch::Contains(": another recording may be writing into "
                                                        "it (its run.json says it is running and "
                                                        "names no process to check)"));
    CHECK(RunData(o.dir).rows() == rows);
    // once it says it has ended there, it is an earlier run: replaced
    meta.replace(meta.find("\"status\": \"running\""), 19, "\"status\": \"finished\"");
    test::write_text(tmp / "run/run.json", meta);
    { Recorder again(sim, o); }
    CHECK(RunData(o.dir).rows() == 1);
}

TEST_CASE("a folder a recorder left in its first milliseconds is an earlier run", "[recorder]") {
    TempDir tmp("recorder_stillborn");
    Simulation sim = snake_sim(2);
    RecordOptions o;
    o.dir = tmp / "run";
    RunContext ctx;
    ctx.script = "snake.lua";
    ctx.files.push_back({"script", "snake.lua", "/x/snake.lua", "-- snake\n", "", 0, ""});
    // killed before run.json existed (as recorders before it was written first could be): the
    // configuration and a temporary series.csv
    fs::create_directories(tmp / "run/config");
    test::write_text(tmp / "run/config/old.lua", "-- old");
    test::write_text(tmp / "run/series.csv.tmp-6952-1", "name,kind");
    test::write_text(tmp / "run/run.json.tmp-6952-2", "{");
    { Recorder rec(sim, o, ctx); }
    CHECK(RunData(o.dir).rows() == 1);
    CHECK(fs::exists(tmp / "run/config/snake.lua"));
    CHECK_FALSE(fs::exists(tmp / "run/config/old.lua"));
    CHECK_FALSE(fs::exists(tmp / "run/series.csv.tmp-6952-1"));
    CHECK_FALSE(fs::exists(tmp / "run/run.json.tmp-6952-2"));
    // anything else in it, or config/ alone, may be the user's: refused, nothing removed
    const std::string refused = ": the folder is not empty and holds no earlier run";
    for (const std::string other : {"notes.txt", "series.csv.tmp-x", "data.csv.tmp-1-2"}) {
        const std::string dir = tmp / ("user-" + other);
        fs::create_directories(dir + "/config");
        test::write_text(dir + "/series.csv.tmp-6952-1", "name,kind");
        test::write_text(dir + "/" + other, "mine");
        o.dir = dir;
        CHECK_THROWS_WITH(Recorder(sim, o), Catch::Contains(refused));
        CHECK(read_text(dir + "/" + other) == "mine");
        CHECK(fs::exists(dir + "/series.csv.tmp-6952-1"));
    }
    fs::create_directories(tmp / "mine/config");
    test::write_text(tmp / "mine/config/settings.lua", "mine");
    o.dir = tmp / "mine";
    CHECK_THROWS_WITH(Recorder(sim, o), Catch::Contains(refused));
    CHECK(read_text(tmp / "mine/config/settings.lua") == "mine");
}

TEST_CASE("a run closed by a signal says so", "[recorder]") {
    TempDir tmp("recorder_signal");
    Simulation sim = snake_sim(2);
    RecordOptions o;
    o.dir = tmp / "run";
    Recorder rec(sim, o);
    sim.run(0.1);
    rec.close("interrupted", "SIGTERM");
    const RunData run(o.dir);
    CHECK(run.meta().status == "interrupted");
    CHECK(run.meta().message == "SIGTERM");
    CHECK(run.meta().last_tick == 100);
    CHECK(run.state() == "interrupted by SIGTERM");
    CHECK_THAT(run.log(), Catch::EndsWith("recording interrupted at t = 0.1 s: 4 rows: SIGTERM\n"));
}

TEST_CASE("run.json is valid UTF-8 whatever bytes it is given", "[recorder]") {
    // names are checked before they get here (printable UTF-8); a script's arguments are not
    TempDir tmp("recorder_utf8");
    Simulation sim(test::chain_world(2, Connection::pitch_pitch));
    RecordOptions o;
    o.dir = tmp / "run";
    RunContext c;
    c.args = {"\xff\xfe-\xc3"};
    { Recorder rec(sim, o, c); }
    const std::string meta = read_text(tmp / "run/run.json");
    // each byte that is not UTF-8 is U+FFFD; no such byte is left in the file
    CHECK(meta.find("\"\xef\xbf\xbd\xef\xbf\xbd-\xef\xbf\xbd\"") != std::string::npos);
    for (const char byte : {'\xff', '\xfe'})
        CHECK(meta.find(byte) == std::string::npos);
    CHECK(RunData(tmp / "run").meta().args ==
          std::vector<std::string>{"\xef\xbf\xbd\xef\xbf\xbd-\xef\xbf\xbd"});
}
