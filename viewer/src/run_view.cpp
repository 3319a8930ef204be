// gaitlab view RUN_FOLDER: a recorded run served to the pages (see run_view.h). The simulation
// is not run again: the scene comes from the run's script run up to its first step (or from
// the pose series alone), the poses of every row from the recorded pose series, and this
// thread plays them back on a timeline the pages drive with the ordinary commands and `seek`.
#include "gaitlab/viewer/run_view.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gaitlab/files.h"
#include "gaitlab/player.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/simulation.h"
#include "gaitlab/terminal.h"
#include "request_json.h"

extern char** environ;

namespace gaitlab::viewer {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// the most numbers the poses of a run may take in memory (rows x bodies x 7): 256 MiB
constexpr std::size_t kMaxPoseNumbers = std::size_t{32} << 20;
// the most series one data or CSV request may ask for
constexpr std::size_t kMaxRequestSeries = 256;
// the most run folders the picker lists
constexpr std::size_t kMaxListed = 300;
// the most folder entries the picker looks at
constexpr std::size_t kMaxVisited = 20000;
// the largest video the page may post
constexpr std::uint64_t kMaxVideoBytes = std::uint64_t{2} << 30;

json series_json(const SeriesInfo& s) {
    return {{"name", s.name},   {"kind", to_string(s.kind)}, {"source", s.source},
            {"value", s.value}, {"joint", s.joint},          {"body", s.body},
            {"unit", s.unit}};
}

// a scene from the pose series alone: each body a small box, no world objects
std::string fallback_scene(const RunData& run, std::vector<double>& poses) {
    const RunMeta& m = run.meta();
    json robots = json::array();
    json bodies = json::array();
    std::vector<std::string> seen;
    for (const SeriesInfo& s : run.series()) {
        if (s.kind != SeriesKind::robot || s.body.empty() || s.value != "x") continue;
        auto r = std::find(seen.begin(), seen.end(), s.source);
        if (r == seen.end()) {
            robots.push_back({{"name", s.source}, {"first_body", bodies.size()}, {"bodies", 0}});
            seen.push_back(s.source);
            r = seen.end() - 1;
        }
        const auto ri = static_cast<std::size_t>(r - seen.begin());
        robots[ri]["bodies"] = robots[ri]["bodies"].get<int>() + 1;
        bodies.push_back(
            {{"name", s.body}, {"robot", ri}, {"shape", "box"}, {"size", {0.04, 0.04, 0.04}}});
    }
    // bodies of one robot together, in the order of the robots
    json ordered = json::array();
    for (std::size_t r = 0; r < robots.size(); ++r) {
        robots[r]["first_body"] = ordered.size();
        for (const json& b : bodies)
            if (b["robot"].get<std::size_t>() == r) ordered.push_back(b);
    }
    poses.clear();
    for (std::size_t i = 0; i < ordered.size(); ++i)
        poses.insert(poses.end(), {0, 0, 0, 1, 0, 0, 0});
    json j;
    j["simulation"] = m.simulation;
    j["dt"] = m.options.dt;
    j["control_every"] = m.options.control_every;
    j["floor"] = {{"enabled", true}, {"friction", 1}};
    j["gravity"] = {0, 0, -9.81};
    j["robots"] = robots;
    j["bodies"] = ordered;
    j["objects"] = json::array();
    j["dynamic"] = 0;
    j["controllers"] = json::array();
    j["sensors"] = json::array();
    return j.dump();
}

}  // namespace

RecordedScene rebuild_scene(const RunData& run, double seconds,
                            const std::function<bool()>& cancel) {
    RecordedScene out;
    const RunMeta& m = run.meta();
    std::string problem;
    if (m.script.empty()) {
        problem = "the run holds no script to rebuild its scene from";
    } else {
        try {
            const std::string script = run.config_file(m.script);
            std::error_code ec;
            if (!fs::is_regular_file(script, ec)) {
                problem = fmt::format("{} is missing", script);
            } else {
                bool captured = false;
                bool timed_out = false;
                std::string error;
                scripting::LuaHost host;
                std::shared_ptr<Player> target;  // goes before the host
                host.set_print(false);
                host.set_reporter([](const std::string&) {});
                scripting::RecordSettings rec;
                rec.disabled = true;  // a rebuild never writes a run folder
                host.set_recording(rec);
                host.seed(m.script_seed);
                host.set_args(script, m.args);
                auto capture = [&](Simulation& sim) {
                    std::vector<ParamControl> controls;
                    out.scene = scene_json(sim, m.simulation, &controls);
                    frame_poses(sim, out.poses);
                    captured = true;
                };
                host.on_player([&](const std::shared_ptr<Player>& p, int index) {
                    if (index == m.simulation) target = p;
                });
                host.set_runner([&](Player& p, int index, long ticks) -> long {
                    if (captured) return 0;
                    if (index == m.simulation) {
                        capture(p.simulation());
                        host.interrupt(SIGTERM);  // the rest of the script is not needed
                        return 0;
                    }
                    return p.simulation().step(ticks);  // an earlier simulation of the script
                });
                // a script that never steps the run's simulation is stopped after `seconds`
                std::mutex mutex;
                std::condition_variable cv;
                bool done = false;
                bool cancelled = false;
                std::thread watchdog([&] {
                    const double until = now_seconds() + seconds;
                    std::unique_lock<std::mutex> lock(mutex);
                    while (
                        !cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) {
                        if (cancel && cancel()) {
                            cancelled = true;
                        } else if (now_seconds() > until) {
                            timed_out = true;
                        } else {
                            continue;
                        }
                        host.interrupt(SIGALRM);
                        return;
                    }
                });
                try {
                    const bool xml =
                        script.size() > 4 && script.compare(script.size() - 4, 4, ".xml") == 0;
                    if (xml) {
                        host.run_simulation_file(script);
                    } else {
                        host.run_file(script);
                    }
                } catch (const std::exception& e) {
                    error = e.what();
                }
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    done = true;
                }
                cv.notify_all();
                watchdog.join();
                if (!captured && target && !timed_out && !cancelled) {
                    capture(target->simulation());
                }
                if (!captured) {
                    if (cancelled) {
                        problem = "interrupted";
                    } else if (timed_out) {
                        problem = fmt::format("its script did not step simulation {} within {} s",
                                              m.simulation, seconds);
                    } else if (!error.empty()) {
                        problem = "its script failed: " + error;
                    } else {
                        problem =
                            fmt::format("its script did not create simulation {}", m.simulation);
                    }
                }
                target.reset();
                host.clear_interrupt();
            }
        } catch (const std::exception& e) {
            problem = e.what();
        }
    }
    if (!problem.empty()) {
        out.problem = problem;
        out.scene = fallback_scene(run, out.poses);
        return out;
    }
    // no sliders and no sensor switches: a recorded run is not steered
    json j = json::parse(out.scene);
    j["controllers"] = json::array();
    j["sensors"] = json::array();
    out.scene = j.dump();
    return out;
}

namespace {

// a run folder as the pages see it
struct Recorded {
    std::string path;  // as the user or the picker named it
    std::unique_ptr<RunData> run;
    std::string scene;
    std::vector<double> times;  // of the rows played back
    std::size_t stride = 0;     // numbers per row: 7 per body and moving object
    std::vector<double> poses;  // times.size() x stride
    bool has_poses = false;
    std::vector<std::string> notes;
    json info;
};

std::shared_ptr<Recorded> load(const std::string& path, double seconds,
                               const std::function<bool()>& cancel = {}) {
    auto r = std::make_shared<Recorded>();
    r->path = path;
    r->run = std::make_unique<RunData>(path);
    const RunData& run = *r->run;
    const std::vector<double> all_times = run.times();  // reads data.csv: FILE:LINE errors
    if (run.truncated()) {
        r->notes.push_back(
            "data.csv ends in a line cut short (the run was killed): that line is left out");
    }
    RecordedScene rs = rebuild_scene(run, seconds, cancel);
    if (!rs.problem.empty()) {
        r->notes.push_back(fmt::format(
            "the scene could not be rebuilt ({}): bodies are drawn as small boxes, without the "
            "world's objects",
            rs.problem));
    }
    r->scene = rs.scene;
    const json scene = json::parse(r->scene);
    r->stride = rs.poses.size();
    // the seven pose series of every body of the scene
    std::vector<std::string> names;
    // the pose slot (bodies, then moving objects) and the first of its seven names
    std::vector<std::pair<std::size_t, std::size_t>> columns;
    const json& robots = scene["robots"];
    const json& bodies = scene["bodies"];
    static const char* const parts[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        const std::string label = robots[bodies[b]["robot"].get<std::size_t>()]["name"];
        const std::string body = bodies[b]["name"];
        std::vector<std::string> seven;
        for (const char* part : parts) {
            for (const SeriesInfo& s : run.series()) {
                if (s.kind == SeriesKind::robot && s.source == label && s.body == body &&
                    s.value == part) {
                    seven.push_back(s.name);
                    break;
                }
            }
        }
        if (seven.size() != 7) continue;
        columns.emplace_back(b, names.size());
        names.insert(names.end(), seven.begin(), seven.end());
    }
    const std::size_t body_columns = columns.size();
    // and of every moving object (series of kind object, recorded since gaitlab records them)
    std::vector<std::string> unrecorded;  // moving objects without their seven series
    int moving = 0;
    for (const json& o : scene["objects"]) {
        const int dynamic = o.value("dynamic", -1);
        if (dynamic < 0) continue;
        ++moving;
        const std::string object = o["name"];
        std::vector<std::string> seven;
        for (const char* part : parts) {
            for (const SeriesInfo& s : run.series()) {
                if (s.kind == SeriesKind::object && s.source == object && s.value == part) {
                    seven.push_back(s.name);
                    break;
                }
            }
        }
        const std::size_t slot = bodies.size() + static_cast<std::size_t>(dynamic);
        if (seven.size() != 7 || slot * 7 + 7 > rs.poses.size()) {
            unrecorded.push_back(object);
            continue;
        }
        columns.emplace_back(slot, names.size());
        names.insert(names.end(), seven.begin(), seven.end());
    }
    std::vector<SeriesData> data;
    if (!names.empty()) data = run.get(names);
    r->has_poses = !data.empty();
    r->times = r->has_poses ? data.front().time : all_times;
    if (!r->has_poses) {
        r->notes.push_back(
            "this run recorded no body poses (series ROBOT.BODY.x ... qz): the 3D view shows the "
            "robots where they start; the plots show every recorded series");
    } else if (body_columns < bodies.size()) {
        r->notes.push_back(
            "some bodies have no recorded pose: they stay where they start in the 3D view");
    }
    if (!unrecorded.empty()) {
        std::string list;
        for (const std::string& o : unrecorded)
            list += (list.empty() ? "" : ", ") + o;
        r->notes.push_back(fmt::format(
            "{} of the world's {} moving objects {} no recorded pose ({}; series OBJECT.x ... qz, "
            "recorded since gaitlab records them): {} where the script put {}",
            unrecorded.size(), moving, unrecorded.size() == 1 ? "has" : "have", list,
            unrecorded.size() == 1 ? "it stays" : "they stay",
            unrecorded.size() == 1 ? "it" : "them"));
    }
    if (r->times.empty()) {
        r->notes.push_back("data.csv holds no complete row yet: there is nothing to play");
        r->times.push_back(0);
    }
    // keep every k-th row when a run is too long to hold every pose
    std::size_t every = 1;
    if (r->stride > 0) {
        while (r->times.size() / every * r->stride > kMaxPoseNumbers)
            ++every;
    }
    if (every > 1) {
        r->notes.push_back(fmt::format(
            "the run is long: the 3D view plays every {}th row (the plots have every row)", every));
    }
    std::vector<double> kept;
    for (std::size_t i = 0; i < r->times.size(); i += every)
        kept.push_back(r->times[i]);
    r->poses.reserve(kept.size() * r->stride);
    for (std::size_t i = 0, row = 0; i < r->times.size(); i += every, ++row) {
        r->poses.insert(r->poses.end(), rs.poses.begin(), rs.poses.end());
        if (!r->has_poses) continue;
        double* p = r->poses.data() + row * r->stride;
        for (const auto& [slot, first] : columns) {
            double v[7];
            bool ok = true;
            for (int k = 0; k < 7; ++k) {
                v[k] = data[first + static_cast<std::size_t>(k)].values[i];
                ok = ok && std::isfinite(v[k]);
            }
            if (ok) std::copy(v, v + 7, p + slot * 7);
        }
    }
    r->times = std::move(kept);

    const RunMeta& m = run.meta();
    json series = json::array();
    for (const SeriesInfo& s : run.series())
        series.push_back(series_json(s));
    r->info = {{"recorded", true},
               {"path", path},
               {"name", m.name},
               {"state", run.state()},
               {"simulation", m.simulation},
               {"dt", m.options.dt},
               {"rows", all_times.size()},
               {"start", r->times.front()},
               {"end", r->times.back()},
               {"poses", r->has_poses},
               {"scene_rebuilt", rs.problem.empty()},
               {"notes", r->notes},
               {"series", series}};
    return r;
}

// the series names of a request: "a,b,c"
std::vector<std::string> requested(const RunRequest& req) {
    const auto it = req.query.find("series");
    if (it == req.query.end() || it->second.empty()) {
        throw ServerError("parameter 'series' expected: series names separated by commas");
    }
    std::vector<std::string> names;
    std::stringstream in(it->second);
    std::string name;
    while (std::getline(in, name, ','))
        if (!name.empty()) names.push_back(name);
    if (names.size() > kMaxRequestSeries) {
        throw ServerError(
            fmt::format("at most {} series at once (got {})", kMaxRequestSeries, names.size()));
    }
    return names;
}

double time_parameter(const RunRequest& req, const char* key, double otherwise) {
    const auto it = req.query.find(key);
    if (it == req.query.end()) return otherwise;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || std::isnan(v)) {
        throw ServerError(fmt::format("parameter '{}': a time in s expected (got '{}')", key,
                                      it->second.substr(0, 40)));
    }
    return v;
}

// a file name made of the run's name: letters, digits, '-', '_' and '.'
std::string safe_name(const std::string& name) {
    std::string out;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
        out += ok ? c : '_';
    }
    if (out.empty() || out[0] == '.') out.insert(0, "run");
    return out.substr(0, 120);
}

}  // namespace

struct RunView::Impl {
    Server server;
    RunViewOptions options;
    std::string start_dir;  // the run's parent: its siblings may be opened

    std::mutex mutex;  // current, changed, video state
    std::shared_ptr<Recorded> current;
    bool changed = true;
    std::mutex load_mutex;  // one load at a time

    std::FILE* video = nullptr;
    std::uint64_t video_bytes = 0;
    bool video_done = false;
    std::string video_error;

    Impl(ServerOptions so, RunViewOptions o) : server(std::move(so)), options(std::move(o)) {}
    ~Impl() {
        if (video != nullptr) std::fclose(video);
    }

    std::shared_ptr<Recorded> now() {
        std::lock_guard<std::mutex> lock(mutex);
        return current;
    }

    // the run folders the picker offers: below the current folder (3 levels down) and beside
    // the first run; never any other path
    json listing() {
        std::vector<std::string> found;
        auto consider = [&found](const fs::path& dir) {
            std::error_code ec;
            if (fs::is_regular_file(dir / "run.json", ec) && !fs::is_symlink(dir, ec)) {
                found.push_back(dir.lexically_normal().string());
            }
        };
        std::error_code ec;
        const fs::path cwd = fs::current_path(ec);
        auto walk = [&](const fs::path& root, int depth, bool relative) {
            fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied,
                                                ec);
            std::size_t visited = 0;
            for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
                // bounded however large the folder is
                if (found.size() >= kMaxListed || ++visited > kMaxVisited) break;
                const fs::path p = it->path();
                const std::string name = p.filename().string();
                if (!it->is_directory(ec) || it->is_symlink(ec) || name.empty() || name[0] == '.' ||
                    name == "node_modules" || name == "config") {
                    if (it->is_directory(ec)) it.disable_recursion_pending();
                    continue;
                }
                if (it.depth() + 1 >= depth) it.disable_recursion_pending();
                consider(relative ? p.lexically_relative(root) : p);
            }
            ec.clear();
        };
        walk(cwd, 3, true);
        if (!start_dir.empty()) {
            const fs::path parent = fs::absolute(start_dir, ec).lexically_normal();
            if (!ec && parent.string().rfind(cwd.string() + "/", 0) != 0 && parent != cwd) {
                walk(parent, 1, false);
            }
        }
        std::sort(found.begin(), found.end());
        found.erase(std::unique(found.begin(), found.end()), found.end());
        json runs = json::array();
        for (const std::string& f : found)
            runs.push_back(f);
        // the current run as the list names it
        const auto cur = now();
        std::string shown = cur ? cur->path : "";
        if (cur) {
            const fs::path here = fs::weakly_canonical(cur->path, ec);
            for (const std::string& f : found) {
                if (!ec && fs::weakly_canonical(f, ec) == here) shown = f;
            }
        }
        return {{"current", shown}, {"runs", runs}};
    }

    RunReply answer(const RunRequest& req) {
        RunReply reply;
        const std::shared_ptr<Recorded> r = now();
        try {
            if (req.path == "/api/run" && req.method == "GET") {
                reply.body = r->info.dump();
            } else if (req.path == "/api/run/data" && req.method == "GET") {
                const std::vector<std::string> names = requested(req);
                const std::vector<SeriesData> d =
                    r->run->get(names, time_parameter(req, "from", -RunData::kInf),
                                time_parameter(req, "to", RunData::kInf));
                json values = json::array();
                for (const SeriesData& s : d)
                    values.push_back(s.values);  // NaN: null
                reply.body = json{
                    {"names", names},
                    {"time", d.empty() ? std::vector<double>{} : d.front().time},
                    {"values",
                     values}}.dump(-1, ' ', false, json::error_handler_t::replace);
            } else if (req.path == "/api/run/csv" && req.method == "GET") {
                const std::vector<std::string> names = requested(req);
                for (const std::string& n : names)
                    r->run->find(n);  // an unknown name: SpecError with suggestions
                std::string tmp = (fs::temp_directory_path() / "gaitlab-csv-XXXXXX").string();
                const int fd = ::mkstemp(tmp.data());
                if (fd < 0) throw IoError("cannot make a temporary file for the CSV");
                ::close(fd);
                try {
                    r->run->write_csv(tmp, names, time_parameter(req, "from", -RunData::kInf),
                                      time_parameter(req, "to", RunData::kInf));
                    reply.body = read_file(tmp);
                } catch (...) {
                    ::unlink(tmp.c_str());
                    throw;
                }
                ::unlink(tmp.c_str());
                reply.type = "text/csv; charset=utf-8";
                reply.filename = safe_name(r->run->meta().name) + ".csv";
            } else if (req.path == "/api/run/list" && req.method == "GET") {
                reply.body = listing().dump(-1, ' ', false, json::error_handler_t::replace);
            } else if (req.path == "/api/run/open" && req.method == "POST") {
                json j;
                std::string error;
                if (!parse_request_json(req.body, j, error)) {
                    throw ServerError("open: " + error +
                                      ": a JSON object {\"path\": \"RUN_FOLDER\"} expected");
                }
                if (!j.is_object() || !j.contains("path") || !j["path"].is_string()) {
                    throw ServerError("open: a JSON object {\"path\": \"RUN_FOLDER\"} expected");
                }
                const std::string path = j["path"];
                bool listed = false;
                const json offered = listing();
                for (const json& p : offered["runs"])
                    listed = listed || p == path;
                if (!listed) {
                    throw ServerError(fmt::format(
                        "open: '{}' is not a run folder the list offers (run folders below the "
                        "folder gaitlab runs in, or beside the first run)",
                        path.substr(0, 200)));
                }
                std::shared_ptr<Recorded> fresh;
                {
                    std::lock_guard<std::mutex> lock(load_mutex);
                    fresh = load(path, options.rebuild_seconds);
                }
                {
                    std::lock_guard<std::mutex> lock(mutex);
                    current = fresh;
                    changed = true;
                }
                reply.body = json{{"ok", true}, {"path", path}}.dump();
            } else if (req.path == "/api/run/video" && req.method == "POST") {
                return take_video(req);
            } else if (req.path == "/api/run/video/done" && req.method == "POST") {
                return end_video(req);
            } else {
                reply.status = 404;
                reply.body = json{{"error", fmt::format("no route {} {} (GET /api/run, "
                                                        "/api/run/data, /api/run/csv, "
                                                        "/api/run/list; POST /api/run/open)",
                                                        req.method, req.path.substr(0, 60))}}
                                 .dump(-1, ' ', false, json::error_handler_t::replace);
            }
        } catch (const ServerError&) {
            throw;
        } catch (const Error& e) {
            throw ServerError(e.what());
        }
        return reply;
    }

    RunReply take_video(const RunRequest& req) {
        std::lock_guard<std::mutex> lock(mutex);
        if (options.video.empty() || video_done) {
            return {404, json{{"error", "no video is being recorded"}}.dump(), "application/json",
                    ""};
        }
        const double offset = time_parameter(req, "offset", -1);
        if (offset != static_cast<double>(video_bytes)) {
            throw ServerError(
                fmt::format("parameter 'offset': {} expected (the bytes so far)", video_bytes));
        }
        if (video_bytes + req.body.size() > kMaxVideoBytes) {
            throw ServerError("the video is larger than 2 GiB");
        }
        if (video == nullptr) {
            video = std::fopen((options.video + ".part").c_str(), "wb");
            if (video == nullptr) {
                video_error =
                    fmt::format("cannot write {}.part: {}", options.video, std::strerror(errno));
                video_done = true;
                throw ServerError(video_error);
            }
        }
        if (std::fwrite(req.body.data(), 1, req.body.size(), video) != req.body.size()) {
            video_error =
                fmt::format("cannot write {}.part: {}", options.video, std::strerror(errno));
            throw ServerError(video_error);
        }
        video_bytes += req.body.size();
        return {200, json{{"ok", true}, {"bytes", video_bytes}}.dump(), "application/json", ""};
    }

    RunReply end_video(const RunRequest& req) {
        std::lock_guard<std::mutex> lock(mutex);
        if (options.video.empty() || video_done) {
            return {404, json{{"error", "no video is being recorded"}}.dump(), "application/json",
                    ""};
        }
        json j = json::parse(req.body, nullptr, false);
        if (j.is_object() && j.contains("error") && j["error"].is_string()) {
            video_error = "the page could not record the video: " + j["error"].get<std::string>();
        }
        if (video != nullptr) {
            if (std::fclose(video) != 0 && video_error.empty()) {
                video_error =
                    fmt::format("cannot write {}.part: {}", options.video, std::strerror(errno));
            }
            video = nullptr;
        }
        if (video_error.empty() && video_bytes == 0) video_error = "the page recorded no video";
        if (video_error.empty()) {
            std::error_code ec;
            fs::rename(options.video + ".part", options.video, ec);
            if (ec) {
                video_error = fmt::format("cannot write {}: {}", options.video, ec.message());
            }
        }
        if (!video_error.empty()) std::remove((options.video + ".part").c_str());
        video_done = true;
        return {200, json{{"ok", video_error.empty()}}.dump(), "application/json", ""};
    }
};

RunView::RunView(const std::string& dir, ServerOptions server, RunViewOptions options) {
    // the folder first: a bad one is reported before anything listens
    std::shared_ptr<Recorded> first = load(dir, options.rebuild_seconds, options.cancel);
    impl_ = std::make_shared<Impl>(std::move(server), std::move(options));
    impl_->current = first;
    // the scene from the start: a page may ask for it before serve() has run once
    impl_->server.publish_scene(first->scene, {}, {});
    std::error_code ec;
    impl_->start_dir = fs::absolute(fs::path(dir), ec).lexically_normal().parent_path().string();
    Impl* impl = impl_.get();
    impl_->server.set_run_provider([impl](const RunRequest& req) { return impl->answer(req); });
    // a recorded run has no live series: the page's live plots find none
    impl_->server.set_live_provider([](const std::map<std::string, std::string>& query) {
        if (query.count("list") != 0) {
            return std::string(
                R"({"series":[],"sample_every":1,"refresh":0.1,"size":2000,"recorded":true})");
        }
        return std::string(R"({"names":[],"time":[],"values":[],"restart":false})");
    });
}

RunView::~RunView() {
    impl_->server.stop();  // no provider call may outlive the view
}

Server& RunView::server() {
    return impl_->server;
}

std::string RunView::url() const {
    return impl_->server.url();
}

double RunView::duration() const {
    const auto r = impl_->now();
    return r->times.back() - r->times.front();
}

std::vector<std::string> RunView::notes() const {
    return impl_->now()->notes;
}

bool RunView::video_done() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->video_done;
}

std::string RunView::video_error() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->video_error;
}

void RunView::serve(const std::function<bool()>& stop) {
    Impl& s = *impl_;
    std::shared_ptr<Recorded> r;
    double t = 0;
    bool playing = false;
    double speed = s.options.video.empty() ? 1 : s.options.video_speed;
    double last = now_seconds();
    double next_frame = 0;
    bool dirty = true;
    auto row_of = [&r](double time) {
        const auto it = std::upper_bound(r->times.begin(), r->times.end(), time);
        return it == r->times.begin() ? std::size_t{0}
                                      : static_cast<std::size_t>(it - r->times.begin() - 1);
    };
    while (!stop()) {
        {
            std::lock_guard<std::mutex> lock(s.mutex);
            if (s.video_done) break;
            if (s.changed) {
                s.changed = false;
                r = s.current;
                t = r->times.front();
                playing = false;
                dirty = true;
                s.server.publish_scene(r->scene, {}, {});
                s.server.publish_message(
                    "info", fmt::format("recorded run {} ({}): {} rows, "
                                        "{:g} s to {:g} s",
                                        r->path, r->run->state(), r->times.size(), r->times.front(),
                                        r->times.back()));
                for (const std::string& n : r->notes)
                    s.server.publish_message("info", n);
            }
        }
        const double start = r->times.front();
        const double end = r->times.back();
        for (const Command& c : s.server.take_commands()) {
            dirty = true;
            switch (c.kind) {
                case Command::Kind::play:
                    if (t >= end) t = start;
                    playing = true;
                    break;
                case Command::Kind::pause:
                    playing = false;
                    break;
                case Command::Kind::step: {
                    playing = false;
                    // `count` ticks on, at least the next row
                    const std::size_t row = row_of(t);
                    const double target =
                        t + static_cast<double>(c.count) * r->run->meta().options.dt;
                    std::size_t next = std::max(row + 1, row_of(target + 1e-12));
                    t = r->times[std::min(next, r->times.size() - 1)];
                    break;
                }
                case Command::Kind::reset:
                    playing = false;
                    t = start;
                    break;
                case Command::Kind::speed:
                    speed = c.value;
                    break;
                case Command::Kind::seek:
                    t = std::clamp(c.value, start, end);
                    break;
                default:  // parameters, sensors, live buffers: a recorded run has none
                    break;
            }
        }
        const double wall = now_seconds();
        if (playing) {
            t += std::isinf(speed) ? end - t : (wall - last) * speed;
            if (t >= end) {
                t = end;
                playing = false;
            }
            dirty = true;
        }
        last = wall;
        if (dirty && wall >= next_frame) {
            const std::size_t row = row_of(t);
            Frame f;
            f.simulation = r->run->meta().simulation;
            f.time = t;
            f.tick = std::lround(r->times[row] / r->run->meta().options.dt);
            f.poses.assign(r->poses.begin() + static_cast<std::ptrdiff_t>(row * r->stride),
                           r->poses.begin() + static_cast<std::ptrdiff_t>((row + 1) * r->stride));
            json state = {{"playing", playing},
                          {"held", !playing},
                          {"running", true},
                          {"finished", false},
                          {"speed", std::isinf(speed) ? json("max") : json(speed)},
                          {"measured", nullptr},
                          {"sensors", json::array()},
                          {"recorded",
                           {{"start", start},
                            {"end", end},
                            {"row", row},
                            {"rows", r->times.size()},
                            {"row_time", r->times[row]}}}};
            f.state = state.dump();
            s.server.publish_frame(std::move(f));
            dirty = false;
            next_frame = wall + 1.0 / s.options.frame_rate;
        }
        s.server.wait_for_commands(playing ? std::max(0.0, next_frame - now_seconds()) : 0.05);
    }
}

std::string find_chromium() {
    if (const char* env = std::getenv("GAITLAB_CHROMIUM"); env != nullptr && *env != '\0') {
        return ::access(env, X_OK) == 0 ? env : "";
    }
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        for (const char* name : {"chromium", "chromium-browser"}) {
            const std::string file = (dir.empty() ? "." : dir) + "/" + name;
            if (::access(file.c_str(), X_OK) == 0) return file;
        }
    }
    return "";
}

std::string render_video(const std::string& dir, const std::string& out, double speed,
                         const std::function<bool()>& stop, const std::string& chromium, int width,
                         int height) {
    if (chromium.empty()) {
        return "--video needs chromium, which is not installed: install it with 'sudo apt "
               "install chromium' (or set GAITLAB_CHROMIUM to a chromium program)";
    }
    {
        std::FILE* f = std::fopen((out + ".part").c_str(), "wb");
        if (f == nullptr) return fmt::format("cannot write {}: {}", out, std::strerror(errno));
        std::fclose(f);
        std::remove((out + ".part").c_str());
    }
    RunViewOptions options;
    options.video = out;
    options.video_speed = speed;
    options.cancel = stop;
    RunView view(dir, ServerOptions{}, options);
    if (stop()) return "interrupted: no video written";
    const double duration = view.duration();
    std::string tmp = (fs::temp_directory_path() / "gaitlab-chromium-XXXXXX").string();
    if (::mkdtemp(tmp.data()) == nullptr) return "cannot make a temporary folder for chromium";
    const std::string log = tmp + "/chromium.log";
    const std::string url =
        fmt::format("{}?video=1&speed={}&size={}x{}", view.url(), speed, width, height);
    print_message(stderr, "gaitlab: drawing %.0f frames of %s in headless chromium\n",
                  duration / speed * 25 + 1, dir.c_str());
    // WebGL in SwiftShader, the page composited in software as chromium does without a GPU
    // (composited by SwiftShader too, every frame would be read back from it: about 10 ms more
    // CPU a frame, docs/performance.md section 9)
    std::vector<std::string> args = {
        chromium,
        "--headless",
        "--no-first-run",
        "--no-default-browser-check",
        "--disable-extensions",
        "--mute-audio",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--ignore-gpu-blocklist",
        "--disable-gpu-compositing",
        "--window-size=" + std::to_string(width + 40) + "," + std::to_string(height + 40),
        "--hide-scrollbars",
        "--user-data-dir=" + tmp + "/profile"};
    if (::geteuid() == 0) args.emplace_back("--no-sandbox");  // chromium refuses root otherwise
    args.push_back(url);
    std::vector<char*> argv;
    for (std::string& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);  // its own group: its helpers end with it
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, chromium.c_str(), &actions, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    auto cleanup = [&tmp] {
        std::error_code ec;
        fs::remove_all(tmp, ec);
    };
    if (rc != 0) {
        cleanup();
        return fmt::format("cannot run {}: {}", chromium, std::strerror(rc));
    }
    // the page draws and encodes 25 frames a second of video: a second each at the most
    const double frames = duration / speed * 25 + 1;
    const double allowed = 60 + frames;
    const double deadline = now_seconds() + allowed;
    int status = 0;
    bool exited = false;
    bool late = false;
    view.serve([&] {
        if (!exited && ::waitpid(pid, &status, WNOHANG) == pid) exited = true;
        late = now_seconds() > deadline;
        return stop() || exited || late;
    });
    if (!exited) {
        ::kill(-pid, SIGTERM);
        ::kill(pid, SIGTERM);
        for (int i = 0; i < 50 && ::waitpid(pid, &status, WNOHANG) == 0; ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (::waitpid(pid, &status, WNOHANG) == 0) {
            ::kill(-pid, SIGKILL);
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
        }
    }
    ::kill(-pid, SIGKILL);  // whatever of its helpers is left in its group
    std::string error;
    if (!view.video_done()) {
        std::string said;
        try {
            said = read_file(log);
        } catch (const std::exception&) {
        }
        // its last lines say why
        std::size_t from = said.size();
        for (int lines = 0; lines < 6 && from > 0; ++lines)
            from = said.rfind('\n', from - 1) == std::string::npos ? 0 : said.rfind('\n', from - 1);
        said = said.substr(from);
        if (stop()) {
            error = "interrupted: no video written";
        } else if (late) {
            error = fmt::format("chromium did not send the video within {:.0f} s{}{}", allowed,
                                said.empty() ? "" : "; it said:\n", said);
        } else {
            error = fmt::format("chromium ended before it sent the video{}{}",
                                said.empty() ? "" : "; it said:\n", said);
        }
        std::remove((out + ".part").c_str());
    } else {
        error = view.video_error();
    }
    cleanup();
    return error;
}

}  // namespace gaitlab::viewer
