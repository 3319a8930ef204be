#include "gaitlab/recorder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "bullet/physics_world.h"
#include "formats/csv.h"
#include "formats/json.h"
#include "formats/run_files.h"
#include "gaitlab/controller.h"
#include "gaitlab/error.h"
#include "gaitlab/event.h"
#include "gaitlab/files.h"
#include "gaitlab/run_data.h"
#include "gaitlab/simulation.h"
#include "gaitlab/version.h"
#include "spec/check.h"

namespace gaitlab {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

// the files a run folder holds; an existing folder with run.json is an earlier run and only
// these are removed from it
constexpr const char* kRunFiles[] = {"run.json", "series.csv", "data.csv", "events.csv", "log.txt"};
// buffered text is written at the latest when it reaches this size, whatever the period
constexpr size_t kMaxBuffer = 1 << 20;

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            if (colon != std::string::npos) {
                size_t start = line.find_first_not_of(' ', colon + 1);
                return start == std::string::npos ? "" : line.substr(start);
            }
        }
    }
    return "unknown";
}

std::string compiler() {
#if defined(__clang__)
    return fmt::format("clang {}.{}.{}", __clang_major__, __clang_minor__, __clang_patchlevel__);
#elif defined(__GNUC__)
    return fmt::format("g++ {}.{}.{}", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
#else
    return "unknown";
#endif
}

// " (process N)" when the folder's run.json names the process that writes it
std::string writer_of(const fs::path& dir) {
    try {
        const std::string path = (dir / "run.json").string();
        const formats::JsonDocument doc(read_file(path), path);
        if (const auto* p = formats::find(doc.root(), "process")) {
            const auto* pid = formats::find(*p, "pid");
            const std::optional<long long> n = pid ? formats::as_integer(*pid) : std::nullopt;
            if (n && *n > 0) return fmt::format(" (process {})", *n);
        }
    } catch (const std::exception&) {
        // a folder being written may be read between two of its writes: say less
    }
    return "";
}

// "run.json.tmp-4242-0": a temporary file of write_file_atomic (files.cpp) for run.json or
// series.csv, left by a process killed between writing and renaming it
bool run_file_leftover(const std::string& name) {
    for (const char* f : {"run.json", "series.csv"}) {
        const std::string prefix = std::string(f) + ".tmp-";
        if (name.rfind(prefix, 0) != 0) continue;
        const std::string rest = name.substr(prefix.size());  // PID-N
        const size_t dash = rest.find('-');
        const auto digits = [](const std::string& t) {
            return !t.empty() && t.find_first_not_of("0123456789") == std::string::npos;
        };
        if (dash != std::string::npos && digits(rest.substr(0, dash)) &&
            digits(rest.substr(dash + 1)))
            return true;
    }
    return false;
}

// whether `p` holds only what a recorder killed in its first milliseconds leaves before its
// run.json exists: temporary files of run.json or series.csv, and its config/ (recorders
// before run.json was written first copied the configuration before it). A folder of
// config/ alone is not taken for one: that may well be the user's.
bool stillborn_run(const fs::path& p) {
    std::error_code ec;
    bool leftover = false;
    for (fs::directory_iterator it(p, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const fs::file_status st = it->symlink_status(ec);
        if (ec) return false;
        if (name == "config" && fs::is_directory(st)) continue;
        if (!fs::is_regular_file(st) || !run_file_leftover(name)) return false;
        leftover = true;
    }
    return !ec && leftover;
}

// why `m` may still be written by a recorder that cannot be checked from here (another host,
// or no process named), for the refusal; "" if it has ended or its process is gone
std::string maybe_running(const RunMeta& m) {
    if (m.status != "running" || liveness(m.process) != Liveness::unknown) return "";
    if (m.process.pid > 0) {
        return fmt::format(
            "another recording may be writing into it on {} (process {}), which "
            "cannot be checked from here",
            m.process.host.empty() ? "another host" : m.process.host, m.process.pid);
    }
    return "another recording may be writing into it (its run.json says it is running and names "
           "no process to check)";
}

// creates the folder (or finds it), locks it against every other recorder, in this process
// or another, then empties it if it is an earlier run folder; anything else is refused.
// Returns the locked folder's descriptor.
int lock_run_dir(const std::string& dir) {
    std::error_code ec;
    const fs::path p(dir);
    if (!fs::exists(p, ec)) {
        fs::create_directories(p, ec);
        if (ec) throw IoError(fmt::format("cannot create run folder {}: {}", dir, ec.message()));
    } else if (!fs::is_directory(p, ec)) {
        throw IoError(fmt::format("cannot record into {}: it exists and is not a folder", dir));
    }
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        throw IoError(fmt::format("cannot record into {}: {}", dir, formats::reason(errno)));
    const auto busy = [&] {
        ::close(fd);
        return IoError(
            fmt::format("cannot record into {}: another recording is writing into it{}; record "
                        "into another folder",
                        dir, writer_of(p)));
    };
    // a lock held by an open recorder; a file system without locks (ENOLCK ...) falls back on
    // the process run.json names
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK) throw busy();
    if (fs::exists(p / "run.json", ec)) {
        bool alive = false;
        std::string unknown;
        try {
            const RunMeta m = RunData::read_meta((p / "run.json").string());
            alive = m.status == "running" && liveness(m.process) == Liveness::alive;
            unknown = maybe_running(m);
        } catch (const Error&) {
            // not readable as a run: emptied like any earlier run folder
        }
        if (alive) throw busy();
        // a run that may still be recording elsewhere (a shared file system): replacing it
        // could empty a colleague's run under it
        if (!unknown.empty()) {
            ::close(fd);
            throw IoError(fmt::format(
                "cannot record into {}: {}; if that run has ended, remove the folder, or record "
                "into another folder",
                dir, unknown));
        }
    } else if (!fs::is_empty(p, ec) && !stillborn_run(p)) {
        ::close(fd);
        throw IoError(fmt::format(
            "cannot record into {}: the folder is not empty and holds no earlier run (record "
            "into a new or empty folder)",
            dir));
    }
    // an earlier run: its run files go, run.json last, so a process killed on the way leaves
    // a folder that is still an earlier run
    std::vector<fs::path> leftovers;
    for (fs::directory_iterator it(p, ec), end; !ec && it != end; it.increment(ec)) {
        if (run_file_leftover(it->path().filename().string())) leftovers.push_back(it->path());
    }
    for (const fs::path& f : leftovers)
        fs::remove(f, ec);
    for (const char* f : kRunFiles) {
        if (std::string_view(f) != "run.json") fs::remove(p / f, ec);
    }
    fs::remove_all(p / "config", ec);
    fs::remove(p / "run.json", ec);
    return fd;
}

// "config/a/../b.lua" and absolute paths cannot leave config/
std::string safe_config_path(const std::string& path) {
    const fs::path p = fs::path(path).lexically_normal();
    if (p.empty() || p.is_absolute() || *p.begin() == "..") {
        throw SpecError(fmt::format("configuration file path '{}' must stay inside config/", path));
    }
    return p.string();
}

}  // namespace

void validate(const RecordOptions& o) {
    if (o.dir.empty()) throw SpecError("the run folder must not be empty");
    // the operating system would stop at the zero and write another folder than the one named
    if (o.dir.find('\0') != std::string::npos) {
        throw SpecError("the run folder '" + o.dir + "' cannot contain a zero byte");
    }
    if (o.record_every < 0) {
        throw SpecError(fmt::format("record_every must be at least 1 (got {})", o.record_every));
    }
    if (!(std::isfinite(o.flush_seconds) && o.flush_seconds >= 0)) {
        throw SpecError(
            fmt::format("flush_seconds must be a non-negative number of seconds (got "
                        "{})",
                        detail::shown(o.flush_seconds)));
    }
}

std::string default_run_dir(const std::string& root, const std::string& name) {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    const std::string base =
        (fs::path(root) / fmt::format("{}-{}", name.empty() ? "run" : name, stamp)).string();
    // the folder is made here, so two runs started in the same second never share one, and
    // the caller knows the folder is its own (to remove if the recording is refused)
    std::error_code ec;
    fs::create_directories(root.empty() ? "." : root, ec);
    std::string dir = base;
    for (int k = 2; k < 10000; ++k) {
        if (fs::create_directory(dir, ec)) return dir;
        // a root that another run made and removed again, its recording refused
        if (ec == std::errc::no_such_file_or_directory) {
            fs::create_directories(root.empty() ? "." : root, ec);
            if (fs::create_directory(dir, ec)) return dir;
        }
        if (ec) throw IoError(fmt::format("cannot create run folder {}: {}", dir, ec.message()));
        dir = fmt::format("{}-{}", base, k);
    }
    throw IoError(fmt::format("cannot create run folder {}: it exists, and so do {}-2 to {}-9999",
                              base, base, base));
}

RunProcess this_process() {
    RunProcess p;
    p.pid = static_cast<long>(::getpid());
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) == 0) p.host = host;
    p.boot_id = formats::boot_id();
    p.start_time = formats::process_start_time(p.pid);
    return p;
}

std::vector<std::pair<std::string, std::string>> provenance() {
    std::vector<std::pair<std::string, std::string>> p;
    p.emplace_back("gaitlab", version());
    p.emplace_back("commit", source_commit());
    p.emplace_back("bullet", physics_version());
    p.emplace_back("compiler", compiler());
    p.emplace_back("cpu", cpu_model());
    p.emplace_back("cores", std::to_string(std::thread::hardware_concurrency()));
    utsname u{};
    if (uname(&u) == 0) {
        p.emplace_back("os", fmt::format("{} {} {}", u.sysname, u.release, u.machine));
    }
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) == 0) p.emplace_back("host", host);
    p.emplace_back("date", utc_now());
    return p;
}

Recorder::Recorder(Simulation& sim, RecordOptions options, RunContext context)
    : sim_(&sim),
      options_(std::move(options)),
      context_(std::move(context)),
      set_(sim, options_.series) {
    validate(options_);
    if (options_.record_every == 0) options_.record_every = sim.options().control_every;
    for (ConfigFile& f : context_.files)
        f.path = safe_config_path(f.path);
    lock_ = lock_run_dir(options_.dir);
    try {
        const fs::path dir(options_.dir);
        started_ = utc_now();
        first_tick_ = sim.ticks();
        last_written_tick_ = first_tick_;
        process_ = this_process();
        // run.json first: a process killed at any point after this leaves an earlier run,
        // which the next recorder replaces, never a folder of stray files that blocks it
        write_meta("running", "");

        for (const ConfigFile& f : context_.files) {
            const fs::path target = dir / "config" / f.path;
            std::error_code ec;
            fs::create_directories(target.parent_path(), ec);
            write_file_atomic(target.string(), f.content);
        }
        std::string list = "name,kind,source,value,joint,body,unit\n";
        for (const SeriesInfo& s : set_.series()) {
            list += formats::csv_line({s.name, to_string(s.kind), s.source, s.value,
                                       s.joint > 0 ? std::to_string(s.joint) : "", s.body, s.unit});
            list += '\n';
        }
        write_file_atomic((dir / "series.csv").string(), list);

        data_ = std::make_unique<formats::AppendFile>((dir / "data.csv").string());
        events_ = std::make_unique<formats::AppendFile>((dir / "events.csv").string());
        log_ = std::make_unique<formats::AppendFile>((dir / "log.txt").string());
        data_buf_ = "time";
        for (const SeriesInfo& s : set_.series()) {
            data_buf_ += ',';
            formats::append_field(data_buf_, s.name);
        }
        data_buf_ += '\n';
        events_buf_ = "tick,time,origin,kind,name,value,detail\n";
        log(fmt::format("recording {} series every {} ticks from t = {} s into {}", set_.size(),
                        options_.record_every, sim.time(), options_.dir));

        values_.assign(set_.size(), 0.0);
        flush_period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(options_.flush_seconds));
        write_row(sim);
        write_buffers();  // the header and the first row are on disk from the start
        observer_ = sim.add_observer([this](const Simulation& s) { on_tick(s); });
        listener_ =
            sim.add_event_listener([this](const Simulation& s, const Event& e) { on_event(s, e); });
    } catch (const std::exception& e) {
        // a recorder that never started says why, and leaves the folder to others (an
        // earlier run folder, which the next recorder replaces). What failed is the
        // recording, not the run (a write, as when a later flush fails): recording_failed,
        // which a replay needs to tell it from a run that a controller or script stopped
        try {
            // not by the path when the folder is gone: that would make a new folder of it
            if (!folder_gone_) write_meta("failed", e.what(), true);
        } catch (const std::exception&) {
        }
        unlock();
        throw;
    }
}

Recorder::~Recorder() {
    try {
        close();
    } catch (const std::exception&) {
        // nowhere to report it from a destructor; close() explicitly to see it
    }
    unlock();
}

void Recorder::unlock() {
    if (lock_ >= 0) {
        ::close(lock_);  // releases the flock
        lock_ = -1;
    }
}

void Recorder::write_meta(const std::string& status, const std::string& message,
                          bool write_failed) {
    const Simulation& sim = *sim_;
    ordered_json j = ordered_json::object();
    j["format"] = "gaitlab run";
    j["format_version"] = 1;
    j["name"] = fs::path(options_.dir).filename().string();
    j["status"] = status;
    if (!message.empty()) j["message"] = message;
    // the data stops at its last complete row, before the run did (a full disk ...)
    if (write_failed) j["recording_failed"] = true;
    j["started"] = started_;
    if (status != "running") j["ended"] = utc_now();
    j["first_tick"] = first_tick_;
    ordered_json& proc = j["process"] = ordered_json::object();
    proc["pid"] = process_.pid;
    proc["host"] = process_.host;
    proc["boot_id"] = process_.boot_id;
    proc["start_time"] = process_.start_time;
    if (status != "running") {
        // what data.csv holds: a failed write drops the rows after the last one written in
        // full, and the data ends there
        j["last_tick"] = write_failed ? last_written_tick_ : sim.ticks();
        j["rows"] = rows_written_;
    }

    ordered_json& s = j["simulation"] = ordered_json::object();
    s["index"] = context_.simulation;
    s["dt"] = sim.options().dt;
    s["control_every"] = sim.options().control_every;
    s["solver_iterations"] = sim.options().solver_iterations;
    s["seed"] = sim.options().seed;
    s["on_controller_error"] =
        sim.options().on_controller_error == ControllerErrorPolicy::stop ? "stop" : "continue";
    s["solver"] = to_string(sim.options().solver);
    // only when used, as in simulation files: runs without it are written as before
    if (sim.options().newton_steps != 0) s["newton_steps"] = sim.options().newton_steps;
    ordered_json& robots = s["robots"] = ordered_json::array();
    for (int r = 0; r < sim.robot_count(); ++r) {
        const RobotSpec& spec = sim.world().robots[static_cast<size_t>(r)].robot;
        robots.push_back({{"label", sim.robot_label(r)},
                          {"name", spec.name},
                          {"bodies", spec.bodies.size()},
                          {"joints", spec.joints.size()}});
    }
    ordered_json& ctls = s["controllers"] = ordered_json::array();
    for (int d = 0; d < sim.drive_count(); ++d) {
        ordered_json joints = ordered_json::array();
        for (int jt : sim.drive_joints(d))
            joints.push_back(jt + 1);
        ctls.push_back({{"label", sim.drive_label(d)},
                        {"name", sim.controller(d).name()},
                        {"robot", sim.robot_label(sim.drive_robot(d))},
                        {"joints", std::move(joints)}});
    }

    ordered_json& rec = j["recording"] = ordered_json::object();
    rec["record_every"] = options_.record_every;
    rec["flush_seconds"] = options_.flush_seconds;
    rec["select"] = options_.series;
    rec["series"] = set_.size();

    ordered_json& run = j["run"] = ordered_json::object();
    run["script"] = context_.script;
    run["args"] = context_.args;
    run["seed"] = context_.script_seed;
    run["started_by"] = context_.started_by;

    ordered_json& files = j["config"] = ordered_json::array();
    for (const ConfigFile& f : context_.files) {
        ordered_json o = {{"role", f.role}, {"path", f.path}, {"origin", f.origin}};
        if (!f.of.empty()) {
            o["of"] = f.of;
            o["version"] = f.version;
        }
        o["hash"] = formats::content_hash(f.content);
        files.push_back(std::move(o));
    }

    ordered_json& prov = j["provenance"] = ordered_json::object();
    for (const auto& [k, v] : provenance())
        prov[k] = v;
    for (const auto& [k, v] : context_.provenance)
        prov[k] = v;

    write_file_atomic((fs::path(options_.dir) / "run.json").string(), formats::dump_json(j));
}

void Recorder::log(std::string_view line) {
    if (closed_) return;
    log_buf_.append(line);
    log_buf_ += '\n';
}

void Recorder::add_config_file(ConfigFile file) {
    if (closed_) return;
    file.path = safe_config_path(file.path);
    const fs::path target = fs::path(options_.dir) / "config" / file.path;
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    try {
        write_file_atomic(target.string(), file.content);
    } catch (const std::exception& e) {
        fail(e);
    }
    context_.files.push_back(std::move(file));
}

void Recorder::write_row(const Simulation& sim) {
    set_.sample(sim, values_.data());
    formats::append_number(data_buf_, sim.time());
    for (double v : values_) {
        data_buf_ += ',';
        formats::append_number(data_buf_, v);
    }
    data_buf_ += '\n';
    buffered_.push_back({data_buf_.size(), sim.ticks()});
    ++rows_;
}

void Recorder::on_tick(const Simulation& sim) {
    set_.tick(sim);
    if (sim.ticks() % options_.record_every != 0) return;
    write_row(sim);
    maybe_flush();
}

void Recorder::maybe_flush() {
    if (data_buf_.size() < kMaxBuffer && std::chrono::steady_clock::now() < next_flush_) return;
    flush();
}

void Recorder::on_event(const Simulation& sim, const Event& e) {
    if (closed_) return;
    events_buf_ += std::to_string(e.tick);
    events_buf_ += ',';
    formats::append_number(events_buf_, static_cast<double>(e.tick) * sim.options().dt);
    events_buf_ += ',';
    events_buf_ += to_string(e.origin);
    events_buf_ += ',';
    events_buf_ += to_string(e.kind);
    events_buf_ += ',';
    formats::append_field(events_buf_, e.name);
    events_buf_ += ',';
    formats::append_number(events_buf_, e.value);
    events_buf_ += ',';
    formats::append_field(events_buf_, e.detail);
    events_buf_ += '\n';
    if (e.kind == EventKind::reset) {
        // time starts again at 0: so do the integrals, and a row shows the state it starts from
        set_.restart();
        write_row(sim);
    } else if (e.kind == EventKind::drive) {
        log(fmt::format(
            "t = {} s: controller '{}' started driving a group; its series are not recorded (the "
            "columns are fixed when recording starts)",
            sim.time(), e.name));
    }
}

void Recorder::flush() {
    if (closed_) return;
    try {
        write_buffers();
    } catch (const std::exception& e) {
        fail(e);
    }
}

void Recorder::write_buffers() {
    if (!data_buf_.empty()) write_data();
    if (!events_buf_.empty()) {
        events_->write(events_buf_);
        events_buf_.clear();
    }
    if (!log_buf_.empty()) {
        log_->write(log_buf_);
        log_buf_.clear();
    }
    next_flush_ = std::chrono::steady_clock::now() + flush_period_;
    // the open files follow their folder wherever it goes: a folder moved or deleted while
    // recording would take the rest of the run along unseen (and run.json, written by its path,
    // would land in a new folder of that name), so the recording stops at the first flush after
    if (lock_ >= 0) check_folder();
}

void Recorder::write_data() {
    try {
        data_->write(data_buf_);
    } catch (const std::exception&) {
        // the write may have put part of the buffer in the file (a disk that fills up on the
        // way): the rows that got there in full are in data.csv, a cut one is dropped by
        // every reader. The file's size says how far it got (if it cannot be told, no row of
        // the buffer is counted).
        struct stat st {};
        std::uint64_t reached = 0;
        if (lock_ >= 0 && ::fstatat(lock_, "data.csv", &st, AT_SYMLINK_NOFOLLOW) == 0 &&
            static_cast<std::uint64_t>(st.st_size) > data_bytes_)
            reached = static_cast<std::uint64_t>(st.st_size) - data_bytes_;
        for (const BufferedRow& row : buffered_) {
            if (row.end > reached) break;
            ++rows_written_;
            last_written_tick_ = row.tick;
        }
        buffered_.clear();
        throw;
    }
    data_bytes_ += data_buf_.size();
    rows_written_ += static_cast<long>(buffered_.size());
    if (!buffered_.empty()) last_written_tick_ = buffered_.back().tick;
    buffered_.clear();
    data_buf_.clear();
}

void Recorder::check_folder() {
    struct stat held {};
    struct stat named {};
    if (::fstat(lock_, &held) != 0) return;
    if (::stat(options_.dir.c_str(), &named) == 0 && named.st_dev == held.st_dev &&
        named.st_ino == held.st_ino)
        return;
    folder_gone_ = true;
    throw IoError(
        held.st_nlink == 0
            ? fmt::format("the run folder {} was deleted while recording: nothing of this run is "
                          "kept",
                          options_.dir)
            : fmt::format("the run folder {} was moved or replaced while recording: what was "
                          "written went with it (its run.json says running: gaitlab data reads "
                          "it as incomplete)",
                          options_.dir));
}

void Recorder::fail(const std::exception& e) {
    const std::string message = e.what();
    if (!closed_) {
        closed_ = true;
        sim_->remove_observer(observer_);
        sim_->remove_event_listener(listener_);
        data_buf_.clear();
        buffered_.clear();
        events_buf_.clear();
        try {
            log_->write(fmt::format("recording stopped at t = {} s: {}\n", sim_->time(), message));
        } catch (const std::exception&) {
            // the disk that refused the data may refuse this too
        }
        try {
            // not by the path when the folder is gone: that would make a new folder of it
            if (!folder_gone_) write_meta("failed", message, true);
        } catch (const std::exception&) {
        }
        data_->close();
        events_->close();
        log_->close();
        unlock();
    }
    throw IoError(folder_gone_ ? message + " (recording stopped)"
                               : message + " (recording stopped; what was written before is kept)");
}

void Recorder::close(const std::string& status, const std::string& message) {
    if (closed_) return;
    sim_->remove_observer(observer_);
    sim_->remove_event_listener(listener_);
    log(message.empty()
            ? fmt::format("recording {} at t = {} s: {} rows", status, sim_->time(), rows_)
            : fmt::format("recording {} at t = {} s: {} rows: {}", status, sim_->time(), rows_,
                          message));
    try {
        write_buffers();
        write_meta(status, message);
    } catch (const std::exception& e) {
        fail(e);
    }
    closed_ = true;
    data_->close();
    events_->close();
    log_->close();
    unlock();
}

}  // namespace gaitlab
