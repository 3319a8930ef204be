#include "gaitlab/viewer/view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>

#include "gaitlab/controller.h"
#include "gaitlab/geometry.h"
#include "gaitlab/live.h"
#include "gaitlab/player.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/sensor.h"
#include "gaitlab/simulation.h"
#include "gaitlab/viewer/editor.h"

namespace gaitlab::viewer {

static_assert(kMaxDelay == kMaxPlayDelay, "the page's delay is the player's");

namespace {

using json = nlohmann::json;
constexpr double kInf = std::numeric_limits<double>::infinity();
// the longest a waiting loop sleeps before it looks at interrupts and the clock again, s
constexpr double kIdle = 0.05;
// a heightfield is drawn from at most this many samples along each side
constexpr int kMaxDrawnSamples = 257;
// live buffers by default: samples kept per series, wall seconds between publications
constexpr int kLiveSize = 2000;
constexpr double kLiveRefresh = 0.1;

// "a,b,c" -> {"a", "b", "c"}
std::vector<std::string> split_commas(const std::string& s) {
    std::vector<std::string> out;
    size_t at = 0;
    while (at <= s.size() && !s.empty()) {
        const size_t end = std::min(s.find(',', at), s.size());
        if (end > at) out.push_back(s.substr(at, end - at));
        at = end + 1;
    }
    return out;
}

json pose_json(const Pose& p) {
    return {p.position.x,    p.position.y,    p.position.z,   p.orientation.w,
            p.orientation.x, p.orientation.y, p.orientation.z};
}

json vec_json(const Vec3& v) {
    return {v.x, v.y, v.z};
}

// the triangles of a solid as one flat list of corners (x y z ...), world frame
json mesh_positions(const Solid& solid) {
    json out = json::array();
    for (const Triangle& t : triangles(solid, 24)) {
        for (const Vec3* v : {&t.a, &t.b, &t.c}) {
            // millimetres are plenty for a picture, and keep the scene small
            out.push_back(std::round(v->x * 1e4) / 1e4);
            out.push_back(std::round(v->y * 1e4) / 1e4);
            out.push_back(std::round(v->z * 1e4) / 1e4);
        }
    }
    return out;
}

// a heightfield with at most kMaxDrawnSamples along each side, for drawing only
Solid drawn_heightfield(const Solid& s) {
    const HeightGrid& g = s.grid;
    if (g.samples_x <= kMaxDrawnSamples && g.samples_y <= kMaxDrawnSamples) return s;
    Solid out = s;
    HeightGrid& d = out.grid;
    d.samples_x = std::min(g.samples_x, kMaxDrawnSamples);
    d.samples_y = std::min(g.samples_y, kMaxDrawnSamples);
    d.heights.assign(static_cast<size_t>(d.samples_x) * static_cast<size_t>(d.samples_y), 0);
    for (int j = 0; j < d.samples_y; ++j) {
        for (int i = 0; i < d.samples_x; ++i) {
            const int si = static_cast<int>(
                std::lround(static_cast<double>(i) * (g.samples_x - 1) / (d.samples_x - 1)));
            const int sj = static_cast<int>(
                std::lround(static_cast<double>(j) * (g.samples_y - 1) / (d.samples_y - 1)));
            d.heights[static_cast<size_t>(j) * static_cast<size_t>(d.samples_x) +
                      static_cast<size_t>(i)] = g.at(si, sj);
        }
    }
    return out;
}

const char* kind_name(Solid::Kind k) {
    switch (k) {
        case Solid::Kind::box:
            return "box";
        case Solid::Kind::cylinder:
            return "cylinder";
        case Solid::Kind::convex:
            return "convex";
        case Solid::Kind::heightfield:
            return "heightfield";
    }
    return "?";
}

// "snake, snake_2": the robots of a simulation, for messages
std::string robots_of(const Simulation& sim) {
    std::string out;
    for (int r = 0; r < sim.robot_count(); ++r)
        out += (out.empty() ? "" : ", ") + sim.robot_label(r);
    return out.empty() ? "no robot" : out;
}

}  // namespace

std::string scene_json(const Simulation& sim, int index, std::vector<ParamControl>* controls) {
    const WorldSpec& w = sim.world();
    json j;
    j["simulation"] = index;
    j["dt"] = sim.options().dt;
    j["control_every"] = sim.options().control_every;
    j["floor"] = {{"enabled", w.floor.enabled}, {"friction", w.floor.friction}};
    j["gravity"] = vec_json(w.gravity);

    json robots = json::array();
    json bodies = json::array();
    for (int r = 0; r < sim.robot_count(); ++r) {
        const RobotSpec& spec = w.robots[static_cast<size_t>(r)].robot;
        robots.push_back({{"name", sim.robot_label(r)},
                          {"first_body", bodies.size()},
                          {"bodies", spec.bodies.size()}});
        for (const BodySpec& b : spec.bodies) {
            bodies.push_back({{"name", b.name},
                              {"robot", r},
                              {"shape", to_string(b.shape)},
                              {"size", vec_json(b.size)}});
        }
    }
    j["robots"] = robots;
    j["bodies"] = bodies;

    // dynamic objects are numbered as Simulation::object numbers them: in world_solids order
    json objects = json::array();
    int dynamic = 0;
    for (const Solid& s : world_solids(w)) {
        json o = {{"name", s.object}, {"kind", kind_name(s.kind)}, {"friction", s.friction}};
        if (s.mass > 0) {
            o["dynamic"] = dynamic++;
        } else {
            o["dynamic"] = -1;
        }
        if (s.kind == Solid::Kind::box || s.kind == Solid::Kind::cylinder) {
            o["size"] = vec_json(s.size);
            o["pose"] = pose_json(s.pose);
        } else {
            o["kind"] = "mesh";
            o["positions"] =
                mesh_positions(s.kind == Solid::Kind::heightfield ? drawn_heightfield(s) : s);
        }
        objects.push_back(std::move(o));
    }
    j["objects"] = objects;
    j["dynamic"] = dynamic;

    json ctls = json::array();
    if (controls) controls->clear();
    for (int d = 0; d < sim.drive_count(); ++d) {
        const Controller& c = sim.controller(d);
        json params = json::array();
        for (const ParamDef& p : c.def().params) {
            params.push_back({{"name", p.name},
                              {"min", p.min},
                              {"max", p.max},
                              {"unit", p.unit},
                              {"default", p.default_value}});
            if (controls) {
                controls->push_back({index, d, sim.drive_label(d), p.name, p.min, p.max, p.unit});
            }
        }
        ctls.push_back({{"drive", d},
                        {"label", sim.drive_label(d)},
                        {"name", c.name()},
                        {"robot", sim.robot_label(sim.drive_robot(d))},
                        {"params", params}});
    }
    j["controllers"] = ctls;

    json sensors = json::array();
    for (int i = 0; i < sim.sensor_count(); ++i) {
        const SensorSpec& spec = sim.sensor(i);
        sensors.push_back({{"index", i},
                           {"name", sensor_label(sim, i)},
                           {"kind", to_string(spec.kind)},
                           {"robot", sim.robot_label(sim.sensor_robot(i))}});
    }
    j["sensors"] = sensors;
    return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string sensor_label(const Simulation& sim, int i) {
    return sim.robot_label(sim.sensor_robot(i)) + "." + sim.sensor(i).name;
}

void frame_poses(const Simulation& sim, std::vector<double>& out) {
    out.clear();
    auto add = [&out](const Pose& p) {
        out.insert(out.end(), {p.position.x, p.position.y, p.position.z, p.orientation.w,
                               p.orientation.x, p.orientation.y, p.orientation.z});
    };
    const WorldSpec& w = sim.world();
    for (int r = 0; r < sim.robot_count(); ++r) {
        const int n = static_cast<int>(w.robots[static_cast<size_t>(r)].robot.bodies.size());
        for (int b = 0; b < n; ++b)
            add(sim.body(r, b).pose);
    }
    for (int k = 0; k < sim.object_count(); ++k)
        add(sim.object(k).pose);
}

// one simulation the view follows
struct View::Session {
    std::shared_ptr<Player> player;
    int index = 0;
    int observer = 0;
    int listener = 0;
    bool held = false;        // a page paused it
    bool scene_dirty = true;  // its drives or their definitions changed
    // its latest series for the pages' plots: made, remade and destroyed on the simulation's
    // thread under Impl::live_mutex; read by the server's threads under it
    std::unique_ptr<LiveBuffers> live;
    LiveOptions live_options;
    double next_frame = 0;  // wall time the next frame is due
    std::string failure;    // why it stopped ("" if it did not)

    Simulation& sim() const { return player->simulation(); }
};

struct View::Impl {
    scripting::LuaHost& host;
    ViewOptions options;
    Server server;
    // oldest first; the last is shown. Changed on the simulation's thread under live_mutex,
    // which the server's threads take to read live series
    std::vector<std::unique_ptr<Session>> sessions;
    mutable std::mutex live_mutex;
    // the session a page chose to show (the command `show`), or none: then the newest. Set on
    // the simulation's thread under live_mutex
    Session* chosen = nullptr;
    Session* running = nullptr;  // the session a run steps now
    bool finished = false;       // the script has ended
    std::string script_error;
    Frame frame;            // reused: its vectors keep their capacity
    bool contacts = false;  // a page asked for the contact points
    std::vector<ContactPoint> points;
    // the environment editor ("Edit world"): the world of the shown simulation as its last
    // scene had it, copied on the simulation's thread for the server's
    std::mutex world_mutex;
    std::shared_ptr<const WorldSpec> world;
    std::string world_file;
    std::unique_ptr<Editor> editor;

    Impl(scripting::LuaHost& h, ServerOptions s, ViewOptions o)
        : host(h), options(o), server(std::move(s)) {}

    Session* shown() const {
        if (chosen) return chosen;
        return sessions.empty() ? nullptr : sessions.back().get();
    }

    // the list of simulations the pages choose from: each one's number, robots and
    // controllers and whether it is shown
    void publish_list() {
        json list = json::array();
        std::vector<int> numbers;
        const Session* on = shown();
        for (const auto& s : sessions) {
            const Simulation& sim = s->sim();
            json robots = json::array();
            for (int r = 0; r < sim.robot_count(); ++r)
                robots.push_back(sim.robot_label(r));
            json drives = json::array();
            for (int d = 0; d < sim.drive_count(); ++d)
                drives.push_back(sim.drive_label(d));
            list.push_back({{"simulation", s->index},
                            {"robots", robots},
                            {"controllers", drives},
                            {"shown", s.get() == on}});
            numbers.push_back(s->index);
        }
        json j = {
            {"shown", on ? on->index : 0}, {"chosen", chosen != nullptr}, {"simulations", list}};
        server.publish_simulations(j.dump(-1, ' ', false, json::error_handler_t::replace),
                                   std::move(numbers));
    }

    Session* find(int index) const {
        if (index == 0) return shown();
        for (const auto& s : sessions) {
            if (s->index == index) return s.get();
        }
        return nullptr;
    }

    void add(const std::shared_ptr<Player>& player, int index) {
        auto s = std::make_unique<Session>();
        s->player = player;
        s->index = index;
        Session* raw = s.get();
        Simulation& sim = player->simulation();
        // frames at the frame rate, read in the record phase of the ticks that reach it
        s->observer = sim.add_observer([this, raw](const Simulation&) {
            if (raw == shown() && steady_seconds() >= raw->next_frame) publish(*raw);
        });
        s->listener = sim.add_event_listener([this, raw](const Simulation&, const Event& e) {
            if (e.kind == EventKind::drive || e.kind == EventKind::reload) raw->scene_dirty = true;
            // hot reload, for the messages panel (failed reloads come through the host)
            if (e.kind == EventKind::reload) {
                server.publish_message(
                    "info", fmt::format("simulation {}: {} reloaded (version {})", raw->index,
                                        e.name, static_cast<long>(e.value)));
            }
            if (e.kind == EventKind::reset) raw->failure.clear();
        });
        raw->live_options.size = kLiveSize;
        raw->live_options.refresh_seconds = kLiveRefresh;
        {
            std::lock_guard<std::mutex> lock(live_mutex);
            sessions.push_back(std::move(s));
            remake_live(*raw);
            // scripts that make many simulations: the view keeps the newest
            while (sessions.size() > static_cast<size_t>(kMaxViewed)) {
                if (chosen == sessions.front().get()) chosen = nullptr;
                detach(*sessions.front());
                sessions.erase(sessions.begin());
            }
        }
        raw->scene_dirty = true;
        publish_list();
        if (chosen && chosen != raw) {
            server.publish_message(
                "info", fmt::format("simulation {} is new; the page still shows simulation {} "
                                    "(choose it in the list to see it)",
                                    index, chosen->index));
        }
        try {
            publish(*raw);
        } catch (const std::exception& e) {
            // a heightfield image that went away since the simulation was built
            server.publish_message(
                "error", fmt::format("simulation {} cannot be shown: {}", index, e.what()));
        }
    }

    // shows `player`'s simulation: moves its session last (the shown one), or adds one
    void show(const std::shared_ptr<Player>& player, int index) {
        for (size_t k = 0; k < sessions.size(); ++k) {
            if (sessions[k]->index != index) continue;
            {
                std::lock_guard<std::mutex> lock(live_mutex);
                std::unique_ptr<Session> s = std::move(sessions[k]);
                sessions.erase(sessions.begin() + static_cast<long>(k));
                sessions.push_back(std::move(s));
                chosen = nullptr;  // the script names it: the pages follow the script again
            }
            publish_list();
            sessions.back()->scene_dirty = true;
            publish(*sessions.back());
            return;
        }
        add(player, index);
    }

    // under live_mutex
    void detach(Session& s) {
        s.live.reset();
        s.sim().remove_observer(s.observer);
        s.sim().remove_event_listener(s.listener);
    }

    // (re)makes the live buffers of `s` with every series it has now; under live_mutex
    void remake_live(Session& s) {
        if (s.live) s.live_options = s.live->options();
        s.live.reset();
        try {
            s.live = std::make_unique<LiveBuffers>(s.sim(), s.live_options);
        } catch (const std::exception& e) {
            server.publish_message(
                "error", fmt::format("simulation {}: no live series ({})", s.index, e.what()));
        }
    }

    // GET /api/live and /api/live/series, on a server thread
    std::string live_json(const std::map<std::string, std::string>& q) const {
        std::lock_guard<std::mutex> lock(live_mutex);
        int index = 0;
        if (auto it = q.find("simulation"); it != q.end() && !it->second.empty()) {
            try {
                index = std::stoi(it->second);
            } catch (const std::exception&) {
                throw ServerError("simulation: a simulation number expected");
            }
        }
        const Session* s = find(index);
        if (!s || !s->live) {
            throw ServerError(fmt::format("no live series for simulation {}", index));
        }
        const LiveBuffers& live = *s->live;
        json j;
        j["simulation"] = s->index;
        if (q.count("list")) {
            json list = json::array();
            for (const SeriesInfo& i : live.series()) {
                list.push_back({{"name", i.name},
                                {"kind", to_string(i.kind)},
                                {"source", i.source},
                                {"value", i.value},
                                {"joint", i.joint},
                                {"body", i.body},
                                {"unit", i.unit}});
            }
            j["series"] = list;
            const LiveOptions o = live.options();
            j["sample_every"] = o.sample_every;
            j["refresh"] = o.refresh_seconds;
            j["size"] = o.size;
            j["dt"] = s->sim().options().dt;
            return j.dump(-1, ' ', false, json::error_handler_t::replace);
        }
        std::vector<std::string> names;
        if (auto it = q.find("series"); it != q.end()) names = split_commas(it->second);
        if (names.empty()) throw ServerError("series: names of live series expected (a,b,c)");
        double since = -kInf;
        if (auto it = q.find("since"); it != q.end() && !it->second.empty()) {
            try {
                since = std::stod(it->second);
            } catch (const std::exception&) {
                throw ServerError("since: a time in seconds expected");
            }
        }
        LiveSnapshot snap;
        try {
            snap = live.snapshot(names);
        } catch (const SpecError& e) {
            throw ServerError(e.what());
        }
        // only what the page has not seen; everything again after a reset (time went back)
        size_t first = 0;
        const bool restart = !snap.time.empty() && snap.time.back() < since;
        if (!restart) {
            while (first < snap.time.size() && snap.time[first] <= since)
                ++first;
        }
        j["version"] = snap.version;
        j["restart"] = restart;
        j["names"] = snap.names;
        j["time"] =
            std::vector<double>(snap.time.begin() + static_cast<long>(first), snap.time.end());
        json values = json::array();
        for (const std::vector<double>& v : snap.values) {
            json col = json::array();
            for (size_t k = first; k < v.size(); ++k)
                col.push_back(std::isfinite(v[k]) ? json(v[k]) : json(nullptr));
            values.push_back(std::move(col));
        }
        j["values"] = std::move(values);
        return j.dump(-1, ' ', false, json::error_handler_t::replace);
    }

    // the frame's state, written by hand: it goes out up to 60 times a second
    std::string state_json(const Session& s) const {
        const Player& p = *s.player;
        const bool waiting = options.wait_for_page && !server.page_seen();
        const bool playing = finished ? p.playing() : !s.held;
        std::string out = fmt::format(
            "{{\"held\":{},\"running\":{},\"playing\":{},\"finished\":{},\"console\":{},"
            "\"speed\":",
            s.held, running == &s && !s.held && !waiting, playing, finished, options.console);
        out += std::isinf(p.speed()) ? std::string("\"max\"") : fmt::format("{}", p.speed());
        out += fmt::format(",\"delay\":{},\"contacts\":{}", p.delay(), contacts);
        const double m = p.measured_speed();
        out += std::isfinite(m) ? fmt::format(",\"measured\":{}", m) : ",\"measured\":null";
        out += ",\"sensors\":[";
        const Simulation& sim = s.sim();
        for (int i = 0; i < sim.sensor_count(); ++i)
            out += (i > 0 ? "," : "") + std::string(sim.sensor_enabled(i) ? "true" : "false");
        out += ']';
        // messages are rare: the JSON library quotes them
        if (!s.failure.empty())
            out += ",\"failure\":" +
                   json(s.failure).dump(-1, ' ', false, json::error_handler_t::replace);
        if (!script_error.empty())
            out += ",\"script_error\":" +
                   json(script_error).dump(-1, ' ', false, json::error_handler_t::replace);
        out += '}';
        return out;
    }

    // publishes the scene if it changed, then a frame of `s` (the shown session only)
    void publish(Session& s) {
        if (&s != shown()) return;
        const Simulation& sim = s.sim();
        if (s.scene_dirty) {
            s.scene_dirty = false;
            // new drives and reloaded controllers bring new series
            if (s.live && s.live->series().size() != SeriesSet(sim).size()) {
                std::lock_guard<std::mutex> lock(live_mutex);
                remake_live(s);
            }
            std::vector<ParamControl> controls;
            std::string scene = scene_json(sim, s.index, &controls);
            std::vector<std::string> sensors;
            for (int i = 0; i < sim.sensor_count(); ++i)
                sensors.push_back(sensor_label(sim, i));
            server.publish_scene(std::move(scene), std::move(controls), std::move(sensors));
            if (editor) {
                auto copy = std::make_shared<const WorldSpec>(sim.world());
                std::lock_guard<std::mutex> lock(world_mutex);
                world = std::move(copy);
            }
        }
        frame.simulation = s.index;
        frame.tick = sim.ticks();
        frame.time = sim.time();
        frame_poses(sim, frame.poses);
        frame.params.clear();
        for (int d = 0; d < sim.drive_count(); ++d) {
            const Controller& c = sim.controller(d);
            for (size_t i = 0; i < c.def().params.size(); ++i)
                frame.params.push_back(c.param(static_cast<int>(i)));
        }
        frame.with_contacts = contacts;
        frame.contacts.clear();
        if (contacts) {
            sim.contacts(points);
            for (const ContactPoint& c : points) {
                frame.contacts.insert(frame.contacts.end(),
                                      {c.position.x, c.position.y, c.position.z, c.normal.x,
                                       c.normal.y, c.normal.z, c.force});
            }
        }
        frame.state = state_json(s);
        server.publish_frame(frame);
        s.next_frame = steady_seconds() + 1.0 / options.frame_rate;
    }

    // what "Edit world" opens: the shown simulation's world, its robots where they are
    EditorSource world_source() {
        std::shared_ptr<const WorldSpec> w;
        {
            std::lock_guard<std::mutex> lock(world_mutex);
            w = world;
        }
        if (!w) throw EditError(409, "there is no simulation to edit yet");
        EditorSource src;
        src.file = world_file;
        src.environment.world = *w;
        src.environment.world.robots.clear();
        for (const PlacedRobot& r : w->robots) {
            // a file places each robot name once: the first robot of a name
            bool placed = false;
            for (const Placement& p : src.environment.placements)
                placed = placed || p.robot == r.robot.name;
            if (placed) continue;
            src.environment.placements.push_back({r.robot.name, r.pose, 0});
            src.robots.push_back(r.robot);
        }
        return src;
    }

    void check_interrupt() const {
        if (host.interrupted() != 0) throw Error(host.interrupt_message());
    }

    // applies the pages' commands, on the host's thread between ticks. `done` and `limit`:
    // the ticks the running session's run has done and must do (a page's step counts)
    void apply(long* done, long limit) {
        if (!server.has_commands()) return;
        std::vector<Session*> touched;
        for (const Command& c : server.take_commands()) {
            Session* s = find(c.simulation);
            if (!s) {
                server.publish_message("error", fmt::format("{}: there is no simulation {} (any "
                                                            "more)",
                                                            to_string(c.kind), c.simulation));
                continue;
            }
            touched.push_back(s);
            Player& p = *s->player;
            Simulation& sim = s->sim();
            switch (c.kind) {
                case Command::Kind::play:
                    if (!s->failure.empty()) {
                        server.publish_message(
                            "error", fmt::format("simulation {} {}: reset it to play again",
                                                 s->index, s->failure));
                        break;
                    }
                    s->held = false;
                    if (finished || running == s) p.play(steady_seconds());
                    break;
                case Command::Kind::pause:
                    s->held = true;
                    p.pause();
                    break;
                case Command::Kind::step: {
                    s->held = true;
                    p.pause();
                    if (running == s) {
                        const long n = std::min(c.count, limit - *done);
                        if (n > 0) *done += sim.step(n);
                    } else if (finished) {
                        step_after(*s, c.count);
                    } else {
                        server.publish_message(
                            "info", fmt::format("simulation {} steps when the script runs it "
                                                "(sim:run) or when the script has finished",
                                                s->index));
                    }
                    break;
                }
                case Command::Kind::reset:
                    sim.reset(Origin::viewer);
                    s->failure.clear();
                    break;
                case Command::Kind::speed:
                    p.set_speed(c.value);
                    break;
                case Command::Kind::delay:
                    p.set_delay(c.value);
                    break;
                case Command::Kind::contacts:
                    contacts = c.value != 0;
                    break;
                case Command::Kind::sensor: {
                    const int i = sim.find_sensor(c.name);
                    if (i < 0) {
                        server.publish_message("error",
                                               fmt::format("there is no sensor '{}'", c.name));
                        break;
                    }
                    sim.set_sensor_enabled(i, c.value != 0, Origin::viewer);
                    break;
                }
                case Command::Kind::seek:  // the server refuses it: a view has no run provider
                    break;
                case Command::Kind::show: {
                    // shown from now on, whatever the script makes next
                    std::lock_guard<std::mutex> lock(live_mutex);
                    chosen = s;
                }
                    s->scene_dirty = true;
                    publish_list();
                    server.publish_message("info", fmt::format("the pages show simulation {} ({})",
                                                               s->index, robots_of(sim)));
                    break;
                case Command::Kind::live:
                    if (s->live) {
                        if (c.sample_every > 0) s->live->set_sample_every(c.sample_every);
                        if (c.refresh >= 0) s->live->set_refresh_seconds(c.refresh);
                        if (c.size > 0) s->live->set_size(c.size);
                    }
                    break;
                case Command::Kind::param:
                    try {
                        if (c.drive < 0 || c.drive >= sim.drive_count()) {
                            throw SpecError("the controller is gone");
                        }
                        sim.controller(c.drive).set_param(c.name, c.value, Origin::viewer);
                    } catch (const SpecError& e) {
                        server.publish_message(
                            "error", fmt::format("{} = {}: {}", c.name, c.value, e.what()));
                    }
                    break;
            }
        }
        for (Session* s : touched)
            publish(*s);
    }

    // steps a session after the script, catching what stops it
    void step_after(Session& s, long ticks) {
        Simulation& sim = s.sim();
        try {
            sim.step(std::min(ticks, kMaxTicks - sim.ticks()));
        } catch (const std::exception& e) {
            fail(s, e);
        }
    }

    void fail(Session& s, const std::exception& e) {
        s.failure = fmt::format("failed at t = {:.3f} s ({})", s.sim().time(), e.what());
        s.player->fail(s.failure);
        server.publish_message("error", fmt::format("simulation {} {}", s.index, s.failure));
    }

    long run(Player& p, int index, long ticks) {
        Session* s = find(index);
        Simulation& sim = p.simulation();
        if (!s || index == 0) return sim.step(ticks);
        Session* outer = running;
        running = s;
        struct Restore {
            Impl& impl;
            Session* outer;
            ~Restore() { impl.running = outer; }
        } restore{*this, outer};
        const bool was_playing = p.playing();
        // a run typed in the console goes, whatever the page held (the page may pause it
        // again); a script's run waits while the page holds it
        if (options.console) s->held = false;
        const WallClock clock = steady_seconds;
        long done = 0;
        bool waited = false;
        while (done < ticks) {
            check_interrupt();
            apply(&done, ticks);
            if (done >= ticks) break;
            if (options.wait_for_page && !server.page_seen()) {
                if (!waited) {
                    waited = true;
                    publish(*s);
                }
                server.wait_for_commands(kIdle);
                continue;
            }
            if (s->held) {
                p.pause();
                server.wait_for_commands(kIdle);
                continue;
            }
            if (!p.playing()) p.play(clock());
            const double wait = p.wait(clock());
            if (wait > 0) {
                server.wait_for_commands(std::min(wait, kIdle));
                continue;
            }
            done += p.advance(clock, -kInf);  // one tick: the run never goes past its end
            if (sim.paused()) break;          // a controller failed under the pause policy
        }
        // outside runs a player plays only if the script set it playing (sim:play())
        if (!was_playing) p.pause();
        publish(*s);
        return done;
    }

    // one round of serving outside the script's runs; returns the wall seconds to wait
    double poll() {
        const bool was = finished;
        finished = true;  // between runs, the pages play and step the simulations themselves
        struct Restore {
            bool& flag;
            bool value;
            ~Restore() { flag = value; }
        } restore{finished, options.console ? was : true};
        const WallClock clock = steady_seconds;
        apply(nullptr, 0);
        double wait = kIdle;
        for (const auto& s : sessions) {
            Player& p = *s->player;
            if (s->held || !p.playing()) continue;
            try {
                p.advance(clock, clock() + 0.02);
            } catch (const std::exception& e) {
                fail(*s, e);
            }
            wait = std::min(wait, p.wait(clock()));
        }
        if (Session* s = shown(); s && steady_seconds() >= s->next_frame) publish(*s);
        return std::max(wait, 0.0);
    }

    void serve(const std::function<bool()>& stop) {
        finished = true;
        for (const auto& s : sessions)
            publish(*s);
        while (!stop()) {
            double wait = poll();
            // hot reload, and what the script left playing with sim:play()
            wait = std::min(wait, host.pump());
            if (wait > 0) server.wait_for_commands(wait);
        }
    }
};

View::View(scripting::LuaHost& host, ServerOptions server, ViewOptions options) {
    if (!(options.frame_rate > 0 && options.frame_rate <= 1000)) {
        throw ServerError("frame rate must be in (0, 1000] frames per second");
    }
    impl_ = std::make_unique<Impl>(host, std::move(server), options);
    Impl* impl = impl_.get();
    // the host keeps this function: once the view is gone it does nothing
    alive_ = std::make_shared<Impl*>(impl);
    host.on_player([alive = alive_](const std::shared_ptr<Player>& p, int index) {
        if (*alive) (*alive)->add(p, index);
    });
    host.set_runner(
        [impl](Player& p, int index, long ticks) { return impl->run(p, index, ticks); });
    impl->server.set_live_provider(
        [impl](const std::map<std::string, std::string>& q) { return impl->live_json(q); });
}

View::~View() {
    *alive_ = nullptr;
    impl_->host.set_runner({});
    // no server thread reads the live buffers (or asks the editor) once they go
    impl_->server.stop();
    std::lock_guard<std::mutex> lock(impl_->live_mutex);
    for (const auto& s : impl_->sessions)
        impl_->detach(*s);
}

Server& View::server() {
    return impl_->server;
}

std::string View::url() const {
    return impl_->server.url();
}

void View::message(const std::string& level, const std::string& text) {
    impl_->server.publish_message(level, text);
}

void View::edit_world(const std::string& file) {
    Impl& m = *impl_;
    std::error_code ec;
    m.world_file = std::filesystem::absolute(file, ec).lexically_normal().string();
    if (!m.editor) {
        m.editor = std::make_unique<Editor>([&m] { return m.world_source(); }, "view");
        m.server.set_world_provider(m.editor->provider());
    }
    // the shown simulation's world, for the first page that opens the editor
    if (Session* s = m.shown()) {
        s->scene_dirty = true;
        m.publish(*s);
    }
}

void View::show(const std::shared_ptr<Player>& player, int index) {
    impl_->show(player, index);
}

double View::poll() {
    return impl_->poll();
}

void View::serve(const std::function<bool()>& stop, const std::string& script_error) {
    impl_->script_error = script_error;
    impl_->serve(stop);
}

}  // namespace gaitlab::viewer
