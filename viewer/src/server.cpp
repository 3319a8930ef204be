#include "gaitlab/viewer/server.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "assets.h"
#include "request_json.h"

namespace gaitlab::viewer {

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

// messages kept for pages that connect later
constexpr std::size_t kMaxMessages = 200;
// a stream with nothing new writes a comment this often, so a page that went away is noticed
constexpr double kHeartbeatSeconds = 1.0;
// Connections served at once, each on a thread of its own (cpp-httplib reads a request's
// headers on the thread that serves it): every open page holds one for its stream, plus its
// commands, and a client that sends its requests slowly holds one while it does. With a fixed
// pool of 36 threads, 100 connections sending a header line a second left no thread for
// anybody else, token or not; threads are now made as connections come, up to this many.
constexpr std::size_t kMaxConnections = 512;
// a connection's reads: a header line, a body's next bytes (browsers send them at once)
constexpr time_t kReadTimeoutSeconds = 2;

// cpp-httplib's TaskQueue as a pool that grows with the connections: an idle thread takes the
// next one, a new thread is made when none is idle, up to kMaxConnections (then connections
// wait their turn); threads idle for a while end
class GrowingPool : public httplib::TaskQueue {
  public:
    ~GrowingPool() override { shutdown(); }

    void enqueue(std::function<void()> fn) override {
        std::lock_guard<std::mutex> lock(mutex_);
        // threads that ended are joined here: they released the lock on their way out
        for (const std::thread::id id : ended_) {
            const auto t = std::find_if(threads_.begin(), threads_.end(),
                                        [&](const std::thread& x) { return x.get_id() == id; });
            if (t == threads_.end()) continue;
            t->join();
            threads_.erase(t);
        }
        ended_.clear();
        jobs_.push_back(std::move(fn));
        if (idle_ == 0 && threads_.size() < kMaxConnections) {
            threads_.emplace_back([this] { work(); });
        } else {
            wake_.notify_one();
        }
    }

    void shutdown() override {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_) return;
            stopping_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_)
            if (t.joinable()) t.join();
    }

  private:
    void work() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            ++idle_;
            const bool woke = wake_.wait_for(lock, std::chrono::seconds(30),
                                             [&] { return stopping_ || !jobs_.empty(); });
            --idle_;
            if (stopping_ || !woke) {  // shut down, or idle for 30 s: the thread ends
                ended_.push_back(std::this_thread::get_id());
                return;
            }
            std::function<void()> fn = std::move(jobs_.front());
            jobs_.pop_front();
            lock.unlock();
            fn();
            lock.lock();
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> jobs_;
    std::vector<std::thread> threads_;
    std::vector<std::thread::id> ended_;  // threads that ended, to join
    std::size_t idle_ = 0;
    bool stopping_ = false;
};

std::string json_error(const std::string& message) {
    return json{{"error", message}}.dump();
}

// a number as messages show it
std::string shown(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return fmt::format("{:g}", v);
}

// a JSON value's type as messages name it
std::string type_of(const json& v) {
    return v.type_name();
}

// a number for a frame: compact, and null for what JSON cannot hold
void append_number(std::string& out, double v, int decimals) {
    if (!std::isfinite(v)) {
        out += "null";
        return;
    }
    fmt::format_to(std::back_inserter(out), "{:.{}f}", v, decimals);
    // "0.100000" -> "0.1": trailing zeros are bytes every page reads 60 times a second
    if (out.find('.', out.size() - static_cast<std::size_t>(decimals) - 1) != std::string::npos) {
        while (out.back() == '0')
            out.pop_back();
        if (out.back() == '.') out.pop_back();
    }
}

std::string encode_frame(const Frame& f) {
    std::string out;
    out.reserve(64 + f.poses.size() * 10 + f.params.size() * 12 + f.state.size());
    fmt::format_to(std::back_inserter(out),
                   "{{\"simulation\":{},\"tick\":{},\"time\":", f.simulation, f.tick);
    append_number(out, f.time, 6);
    out += ",\"poses\":[";
    for (std::size_t i = 0; i < f.poses.size(); ++i) {
        if (i > 0) out += ',';
        append_number(out, f.poses[i], 5);
    }
    out += "],\"params\":[";
    for (std::size_t i = 0; i < f.params.size(); ++i) {
        if (i > 0) out += ',';
        if (std::isfinite(f.params[i])) {
            out += fmt::format("{}", f.params[i]);
        } else {
            out += "null";
        }
    }
    out += ']';
    if (f.with_contacts) {
        out += ",\"contacts\":[";
        for (std::size_t i = 0; i < f.contacts.size(); ++i) {
            if (i > 0) out += ',';
            append_number(out, f.contacts[i], i % 7 == 6 ? 3 : 4);
        }
        out += ']';
    }
    out += ",\"state\":";
    out += f.state.empty() ? "{}" : f.state;
    out += '}';
    return out;
}

// one server-sent event; `data` holds no line break (JSON as dump() writes it)
std::string sse(const char* event, const std::string& data) {
    std::string out;
    out.reserve(data.size() + 32);
    out += "event: ";
    out += event;
    out += "\ndata: ";
    out += data;
    out += "\n\n";
    return out;
}

// constant time, so a token cannot be guessed a character at a time
bool same_token(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;  // every token has 32 digits: no secret here
    unsigned char diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
}

// the token a request carries: ?token=..., or the cookie the page got with it
std::string request_token(const httplib::Request& req) {
    if (req.has_param("token")) return req.get_param_value("token");
    const std::string cookies = req.get_header_value("Cookie");
    const std::string key = "gaitlab_token=";
    for (std::size_t at = cookies.find(key); at != std::string::npos;
         at = cookies.find(key, at + 1)) {
        if (at == 0 || cookies[at - 1] == ' ' || cookies[at - 1] == ';') {
            const std::size_t start = at + key.size();
            return cookies.substr(start, cookies.find(';', start) - start);
        }
    }
    return "";
}

// why binding host:port fails, found by binding a socket of our own (cpp-httplib only says
// that it failed)
std::string bind_failure(const std::string& host, int port) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    addrinfo* res = nullptr;
    const std::string service = std::to_string(port);
    const int rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &res);
    if (rc != 0) {
        return fmt::format(
            "'{}' is not an address of this machine ({}); give --host an address "
            "such as 127.0.0.1 or 0.0.0.0",
            host, ::gai_strerror(rc));
    }
    std::string why = "unknown error";
    for (addrinfo* a = res; a; a = a->ai_next) {
        const int fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
        if (fd < 0) {
            why = std::strerror(errno);
            continue;
        }
        const int yes = 1;
        ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0) {
            ::close(fd);
            why = "it could not listen there";
            continue;
        }
        const int e = errno;
        ::close(fd);
        if (e == EADDRINUSE) {
            why = fmt::format(
                "port {} is in use (choose another with --port N, or leave --port "
                "out for any free port)",
                port);
        } else if (e == EACCES) {
            why = fmt::format(
                "port {} needs privileges (choose one above 1023 with --port N, or "
                "leave --port out for any free port)",
                port);
        } else if (e == EADDRNOTAVAIL) {
            why = fmt::format(
                "'{}' is not an address of this machine (try 127.0.0.1, or 0.0.0.0 "
                "for every interface)",
                host);
        } else {
            why = std::strerror(e);
        }
        break;
    }
    ::freeaddrinfo(res);
    return why;
}

}  // namespace

const char* to_string(Command::Kind kind) {
    switch (kind) {
        case Command::Kind::play:
            return "play";
        case Command::Kind::pause:
            return "pause";
        case Command::Kind::step:
            return "step";
        case Command::Kind::reset:
            return "reset";
        case Command::Kind::speed:
            return "speed";
        case Command::Kind::param:
            return "param";
        case Command::Kind::live:
            return "live";
        case Command::Kind::sensor:
            return "sensor";
        case Command::Kind::seek:
            return "seek";
        case Command::Kind::show:
            return "show";
        case Command::Kind::delay:
            return "delay";
        case Command::Kind::contacts:
            return "contacts";
    }
    return "?";
}

bool is_loopback(const std::string& host) {
    if (host == "localhost" || host == "::1" || host == "[::1]") return true;
    in_addr a{};
    if (::inet_pton(AF_INET, host.c_str(), &a) == 1) return (ntohl(a.s_addr) >> 24) == 127;
    return false;
}

std::string random_token() {
    std::ifstream in("/dev/urandom", std::ios::binary);
    unsigned char bytes[16] = {};
    if (!in.read(reinterpret_cast<char*>(bytes), sizeof bytes)) {
        throw ServerError("cannot make a token: /dev/urandom cannot be read");
    }
    std::string out;
    for (unsigned char b : bytes)
        out += fmt::format("{:02x}", b);
    return out;
}

struct Server::State {
    ServerOptions options;
    httplib::Server http;
    std::thread thread;
    int port = 0;
    std::vector<std::string> hosts;  // Host headers accepted when there is no token

    mutable std::mutex mutex;
    std::condition_variable changed;  // scene, frame or messages changed, or stopping
    bool stopping = false;
    std::uint64_t scene_version = 0;
    std::shared_ptr<const std::string> scene;  // as an SSE event
    std::uint64_t simulations_version = 0;
    std::string simulations_json;  // the list the pages choose from ("" until published)
    std::vector<int> simulation_numbers;
    socket_t listening = -1;  // the socket cpp-httplib listens on
    std::vector<ParamControl> controls;
    std::vector<std::string> sensors;
    std::uint64_t frame_version = 0;
    std::shared_ptr<const Frame> frame;
    std::shared_ptr<const std::string> frame_event;              // encoded once, on first demand
    std::deque<std::pair<std::uint64_t, std::string>> messages;  // SSE events, numbered
    std::uint64_t message_version = 0;

    std::mutex command_mutex;
    std::condition_variable command_arrived;
    std::deque<Command> commands;
    std::atomic<bool> pending{false};

    std::mutex live_mutex;
    LiveProvider live;
    RunProvider run;      // under live_mutex
    WorldProvider world;  // under live_mutex
    bool stopped = false;

    std::atomic<int> streams{0};
    std::atomic<bool> page_seen{false};
    std::atomic<std::uint64_t> frames{0}, sent{0}, dropped{0}, accepted{0}, refused{0};

    void refuse(httplib::Response& res, int status, const std::string& message) {
        ++refused;
        res.status = status;
        res.set_content(json_error(message), "application/json");
    }

    // the latest frame as an SSE event (encoded by the first stream that wants it)
    std::shared_ptr<const std::string> frame_text(std::unique_lock<std::mutex>&) {
        if (!frame) return nullptr;
        if (!frame_event)
            frame_event = std::make_shared<const std::string>(sse("frame", encode_frame(*frame)));
        return frame_event;
    }

    bool seekable = false;  // a run provider is set (under mutex)
    Command parse_command(const std::string& body, std::string& error) const;
    void routes();
};

Command Server::State::parse_command(const std::string& body, std::string& error) const {
    Command c;
    json j;
    if (!parse_request_json(body, j, error)) {
        error += ": a command is an object such as {\"command\": \"pause\"}";
        return c;
    }
    if (!j.is_object()) {
        error = fmt::format(
            "a command is a JSON object such as {{\"command\": \"pause\"}} (got "
            "{})",
            type_of(j));
        return c;
    }
    const auto name = j.find("command");
    if (name == j.end() || !name->is_string()) {
        error =
            "field 'command' expected: play, pause, step, reset, speed, delay, param, live, "
            "sensor, contacts, seek or show";
        return c;
    }
    const std::string what = name->get<std::string>();
    static const std::vector<std::pair<std::string, Command::Kind>> kinds = {
        {"play", Command::Kind::play},   {"pause", Command::Kind::pause},
        {"step", Command::Kind::step},   {"reset", Command::Kind::reset},
        {"speed", Command::Kind::speed}, {"param", Command::Kind::param},
        {"live", Command::Kind::live},   {"sensor", Command::Kind::sensor},
        {"delay", Command::Kind::delay}, {"contacts", Command::Kind::contacts},
        {"seek", Command::Kind::seek},   {"show", Command::Kind::show}};
    const auto k =
        std::find_if(kinds.begin(), kinds.end(), [&](const auto& p) { return p.first == what; });
    if (k == kinds.end()) {
        error = fmt::format(
            "unknown command '{}': play, pause, step, reset, speed, delay, param, live, sensor, "
            "contacts, seek or show expected",
            what.substr(0, 40));
        return c;
    }
    c.kind = k->second;
    // fields each command takes; any other is a mistake worth saying
    std::vector<std::string> allowed = {"command", "simulation"};
    if (c.kind == Command::Kind::step) allowed.push_back("ticks");
    if (c.kind == Command::Kind::speed || c.kind == Command::Kind::delay)
        allowed.push_back("value");
    if (c.kind == Command::Kind::contacts) allowed.push_back("enabled");
    if (c.kind == Command::Kind::param) {
        allowed.insert(allowed.end(), {"controller", "name", "value"});
    }
    if (c.kind == Command::Kind::live)
        allowed.insert(allowed.end(), {"sample_every", "refresh", "size"});
    if (c.kind == Command::Kind::sensor) allowed.insert(allowed.end(), {"name", "enabled"});
    if (c.kind == Command::Kind::seek) allowed.push_back("time");
    for (const auto& item : j.items()) {
        if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
            std::string list;
            for (const std::string& a : allowed)
                list += (list.empty() ? "" : ", ") + a;
            error = fmt::format("command '{}' takes no field '{}' (it takes {})", what,
                                item.key().substr(0, 40), list);
            return c;
        }
    }
    if (const auto s = j.find("simulation"); s != j.end()) {
        if (!s->is_number_integer() || s->get<long long>() < 0 || s->get<long long>() > 1000000) {
            error = "field 'simulation': a simulation number (from 1) expected";
            return c;
        }
        c.simulation = s->get<int>();
    }
    // a simulation named must be one there is, for every command (not only show): a command
    // for no simulation was answered ok and refused later, on the event stream only. (A
    // recorded run publishes no list: its page names the run's one simulation.)
    std::string numbers;
    for (int n : simulation_numbers)
        numbers += (numbers.empty() ? "" : ", ") + std::to_string(n);
    if (c.simulation != 0 && !simulation_numbers.empty() &&
        std::find(simulation_numbers.begin(), simulation_numbers.end(), c.simulation) ==
            simulation_numbers.end()) {
        error = fmt::format("{}: there is no simulation {} (there {} {})", what, c.simulation,
                            simulation_numbers.size() == 1 ? "is" : "are", numbers);
        return c;
    }
    if (c.kind == Command::Kind::step) {
        c.count = 1;
        if (const auto t = j.find("ticks"); t != j.end()) {
            if (!t->is_number_integer() || t->get<long long>() < 1 ||
                t->get<long long>() > 1000000) {
                error = "field 'ticks': a whole number of ticks in [1, 1000000] expected";
                return c;
            }
            c.count = t->get<long>();
        }
    }
    if (c.kind == Command::Kind::speed) {
        const auto v = j.find("value");
        if (v != j.end() && v->is_string() && v->get<std::string>() == "max") {
            c.value = std::numeric_limits<double>::infinity();
        } else if (v == j.end() || !v->is_number() || !(v->get<double>() > 0) ||
                   !(v->get<double>() <= 1000)) {
            error =
                "field 'value': a real-time factor in (0, 1000], or \"max\" for as fast as "
                "possible, expected";
            return c;
        } else {
            c.value = v->get<double>();
        }
    }
    if (c.kind == Command::Kind::delay) {
        const auto v = j.find("value");
        if (v == j.end() || !v->is_number() || !(v->get<double>() >= 0) ||
            !(v->get<double>() <= kMaxDelay)) {
            error = fmt::format(
                "field 'value': wall seconds between two physics steps in [0, {}] expected",
                shown(kMaxDelay));
            return c;
        }
        c.value = v->get<double>();
    }
    if (c.kind == Command::Kind::contacts) {
        const auto on = j.find("enabled");
        if (on == j.end() || !on->is_boolean()) {
            error = "field 'enabled': true (frames carry the contact points) or false expected";
            return c;
        }
        c.value = on->get<bool>() ? 1 : 0;
    }
    if (c.kind == Command::Kind::sensor) {
        const auto n = j.find("name");
        const auto on = j.find("enabled");
        if (n == j.end() || !n->is_string() || on == j.end() || !on->is_boolean()) {
            error =
                "fields 'name' (\"<robot>.<sensor>\", as the scene lists sensors) and "
                "'enabled' (true or false) expected";
            return c;
        }
        c.name = n->get<std::string>();
        c.value = on->get<bool>() ? 1 : 0;
        if (std::find(sensors.begin(), sensors.end(), c.name) == sensors.end()) {
            std::string names;
            for (const std::string& x : sensors)
                names += (names.empty() ? "" : ", ") + x;
            error = fmt::format("there is no sensor '{}' (there {} {})", c.name.substr(0, 60),
                                sensors.size() == 1 ? "is" : "are", names.empty() ? "none" : names);
            return c;
        }
    }
    if (c.kind == Command::Kind::show) {
        if (simulation_numbers.empty()) {
            error =
                "show: there are no simulations to choose from here (a recorded run, or no "
                "simulation yet)";
            return c;
        }
        if (c.simulation == 0) {
            error = fmt::format(
                "show: field 'simulation' expected: the number of the simulation "
                "to show ({})",
                numbers);
            return c;
        }
    }
    if (c.kind == Command::Kind::seek) {
        if (!seekable) {
            error = "seek: only a recorded run has a timeline (gaitlab view RUN_FOLDER)";
            return c;
        }
        const auto t = j.find("time");
        if (t == j.end() || !t->is_number() || !std::isfinite(t->get<double>())) {
            error = "field 'time': the time to go to, in s, expected";
            return c;
        }
        c.value = t->get<double>();
    }
    if (c.kind == Command::Kind::live) {
        if (const auto v = j.find("sample_every"); v != j.end()) {
            if (!v->is_number_integer() || v->get<long long>() < 1 ||
                v->get<long long>() > 1000000) {
                error = "field 'sample_every': ticks between samples in [1, 1000000] expected";
                return c;
            }
            c.sample_every = v->get<int>();
        }
        if (const auto v = j.find("refresh"); v != j.end()) {
            if (!v->is_number() || !(v->get<double>() >= 0 && v->get<double>() <= 10)) {
                error = "field 'refresh': seconds between publications in [0, 10] expected";
                return c;
            }
            c.refresh = v->get<double>();
        }
        if (const auto v = j.find("size"); v != j.end()) {
            if (!v->is_number_integer() || v->get<long long>() < 1 ||
                v->get<long long>() > 100000) {
                error = "field 'size': samples kept per series in [1, 100000] expected";
                return c;
            }
            c.size = v->get<int>();
        }
    }
    if (c.kind == Command::Kind::param) {
        const auto ctl = j.find("controller");
        const auto pn = j.find("name");
        const auto v = j.find("value");
        if (ctl == j.end() || !ctl->is_string() || pn == j.end() || !pn->is_string()) {
            error =
                "fields 'controller' and 'name' expected: the controller's label and the "
                "parameter's name, as the scene lists them";
            return c;
        }
        const std::string label = ctl->get<std::string>();
        c.name = pn->get<std::string>();
        const int sim = c.simulation;
        // the newest simulation when none is named: the one the scene describes
        int newest = 0;
        for (const ParamControl& p : controls)
            newest = std::max(newest, p.simulation);
        const int target = sim == 0 ? newest : sim;
        const ParamControl* found = nullptr;
        bool controller_known = false;
        for (const ParamControl& p : controls) {
            if (p.simulation != target || p.controller != label) continue;
            controller_known = true;
            if (p.name == c.name) found = &p;
        }
        if (!controller_known) {
            error =
                fmt::format("simulation {} has no controller '{}'", target, label.substr(0, 40));
            return c;
        }
        if (!found) {
            std::string names;
            for (const ParamControl& p : controls) {
                if (p.simulation == target && p.controller == label) {
                    names += (names.empty() ? "" : ", ") + p.name;
                }
            }
            error = fmt::format("controller '{}' has no parameter '{}' (it has {})", label,
                                c.name.substr(0, 40), names.empty() ? "none" : names);
            return c;
        }
        if (v == j.end() || !v->is_number()) {
            error = fmt::format("field 'value': a number in [{}, {}] {} expected for {}.{}",
                                shown(found->min), shown(found->max), found->unit, label, c.name);
            return c;
        }
        c.value = v->get<double>();
        if (!(c.value >= found->min && c.value <= found->max)) {
            error = fmt::format("{}.{} must be in [{}, {}] {} (got {})", label, c.name,
                                shown(found->min), shown(found->max), found->unit, shown(c.value));
            return c;
        }
        c.simulation = target;
        c.drive = found->drive;
    }
    return c;
}

void Server::State::routes() {
    // every request: the token when there is one, else a Host header naming this server (a
    // page elsewhere cannot reach a loopback server through a name it controls)
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (!options.token.empty()) {
            if (!same_token(request_token(req), options.token)) {
                refuse(res, 403,
                       "forbidden: this viewer needs the token of the address gaitlab printed "
                       "(?token=...)");
                return httplib::Server::HandlerResponse::Handled;
            }
        } else {
            const std::string host = req.get_header_value("Host");
            if (std::find(hosts.begin(), hosts.end(), host) == hosts.end()) {
                refuse(res, 403,
                       fmt::format("forbidden: this viewer answers only to "
                                   "http://127.0.0.1:{}/ (Host header '{}')",
                                   port, host.substr(0, 80)));
                return httplib::Server::HandlerResponse::Handled;
            }
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });

    for (const Asset& a : assets()) {
        const std::string path = a.path == "index.html" ? "/" : "/" + a.path;
        const Asset* asset = &a;
        http.Get(path, [this, asset](const httplib::Request&, httplib::Response& res) {
            res.set_content(asset->data, asset->size, std::string(asset->type) + "; charset=utf-8");
            res.set_header("Cache-Control", "no-cache");
            // the page's own requests (scripts, styles, the event stream) carry the token as a
            // cookie of this server only
            if (!options.token.empty()) {
                res.set_header("Set-Cookie", "gaitlab_token=" + options.token +
                                                 "; Path=/; HttpOnly; SameSite=Strict");
            }
        });
    }

    http.Get("/api/scene", [this](const httplib::Request&, httplib::Response& res) {
        std::unique_lock<std::mutex> lock(mutex);
        if (!scene) {
            res.set_content("{\"simulation\":0}", "application/json");
            return;
        }
        // the stored event without its "event: scene\ndata: " and "\n\n"
        const std::string& s = *scene;
        const std::size_t start = s.find("data: ") + 6;
        res.set_content(s.substr(start, s.size() - start - 2), "application/json");
    });

    http.Get("/api/simulations", [this](const httplib::Request&, httplib::Response& res) {
        std::unique_lock<std::mutex> lock(mutex);
        res.set_content(simulations_json.empty() ? "{\"simulations\":[]}" : simulations_json,
                        "application/json");
    });

    // live series: answered on this thread by the provider (the view reads the live buffers,
    // which are made for readers on other threads)
    auto live_route = [this](bool list) {
        return [this, list](const httplib::Request& req, httplib::Response& res) {
            LiveProvider fn;
            {
                std::lock_guard<std::mutex> lock(live_mutex);
                fn = live;
            }
            if (!fn) {
                refuse(res, 404, "no live series here");
                return;
            }
            std::map<std::string, std::string> query;
            for (const auto& [key, value] : req.params)
                query[key] = value;
            if (list) query["list"] = "1";
            try {
                res.set_content(fn(query), "application/json");
            } catch (const ServerError& e) {
                refuse(res, 400, e.what());
            }
        };
    };
    http.Get("/api/live", live_route(false));
    http.Get("/api/live/series", live_route(true));

    // a recorded run (run_view.cpp): answered on this thread by the provider
    auto run_route = [this](const httplib::Request& req, httplib::Response& res) {
        RunProvider fn;
        {
            std::lock_guard<std::mutex> lock(live_mutex);
            fn = run;
        }
        if (!fn) {
            // the page asks whether there is a recorded run: a live view says no
            if (req.method == "GET" && req.path == "/api/run") {
                res.set_content("{\"recorded\":false}", "application/json");
                return;
            }
            refuse(res, 404, "no recorded run here (gaitlab view RUN_FOLDER serves one)");
            return;
        }
        RunRequest r;
        r.method = req.method;
        r.path = req.path;
        r.type = req.get_header_value("Content-Type");
        if (r.method == "POST" && r.type.rfind("application/json", 0) != 0 &&
            r.type.rfind("application/octet-stream", 0) != 0) {
            refuse(res, 415, "send application/json (or application/octet-stream for data)");
            return;
        }
        for (const auto& [key, value] : req.params)
            if (key != "token") r.query[key] = value;
        r.body = req.body;
        try {
            RunReply reply = fn(r);
            res.status = reply.status;
            if (reply.status >= 400) ++refused;
            if (!reply.filename.empty()) {
                res.set_header("Content-Disposition",
                               "attachment; filename=\"" + reply.filename + "\"");
            }
            res.set_content(std::move(reply.body), reply.type);
        } catch (const ServerError& e) {
            refuse(res, 400, e.what());
        }
    };
    http.Get(R"(/api/run(/[a-z]+)*)", run_route);
    http.Post(R"(/api/run(/[a-z]+)*)", run_route);
    // the environment editor (editor.h): answered on this thread by its provider
    auto world_route = [this](const char* action) {
        return [this, action](const httplib::Request& req, httplib::Response& res) {
            WorldProvider fn;
            {
                std::lock_guard<std::mutex> lock(live_mutex);
                fn = world;
            }
            if (!fn) {
                // the page asks whether there is a world to edit: a recorded run says no
                if (req.method == "GET") {
                    res.set_content("{\"editable\":false}", "application/json");
                    return;
                }
                refuse(res, 404, "no world to edit here");
                return;
            }
            if (req.method == "POST" &&
                req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
                refuse(res, 415, "an edit is sent as Content-Type: application/json");
                return;
            }
            const Reply r = fn(action, req.body);
            if (r.status != 200) ++refused;
            res.status = r.status;
            res.set_content(r.body, "application/json");
        };
    };
    http.Get("/api/world", world_route("open"));
    http.Post("/api/world/shape", world_route("shape"));
    http.Post("/api/world/check", world_route("check"));
    http.Post("/api/world/save", world_route("save"));

    http.Get("/api/status", [this](const httplib::Request&, httplib::Response& res) {
        json j;
        j["streams"] = streams.load();
        j["frames"] = frames.load();
        j["sent"] = sent.load();
        j["dropped"] = dropped.load();
        j["commands"] = accepted.load();
        j["refused"] = refused.load();
        res.set_content(j.dump(), "application/json");
    });

    http.Post("/api/command", [this](const httplib::Request& req, httplib::Response& res) {
        // a JSON body only: a form or text/plain post is what a page of another site can send
        // without asking (CORS lets it through), an application/json one is not
        const std::string type = req.get_header_value("Content-Type");
        if (type.rfind("application/json", 0) != 0) {
            refuse(res, 415, "a command is sent as Content-Type: application/json");
            return;
        }
        // the payload limit is the world editor's; commands are small
        if (req.body.size() > kMaxCommandBytes) {
            refuse(res, 413, fmt::format("a command is at most {} bytes", kMaxCommandBytes));
            return;
        }
        std::string error;
        Command c;
        {
            std::unique_lock<std::mutex> lock(mutex);
            c = parse_command(req.body, error);
        }
        if (!error.empty()) {
            refuse(res, 400, error);
            return;
        }
        {
            std::lock_guard<std::mutex> lock(command_mutex);
            if (commands.size() >= static_cast<std::size_t>(kMaxQueuedCommands)) {
                refuse(res, 503,
                       fmt::format("the simulation is busy: {} commands wait already (try "
                                   "again in a moment)",
                                   kMaxQueuedCommands));
                return;
            }
            commands.push_back(c);
            pending.store(true, std::memory_order_release);
        }
        command_arrived.notify_all();
        ++accepted;
        res.set_content(json{{"ok", true}, {"command", to_string(c.kind)}}.dump(),
                        "application/json");
    });

    http.Get("/api/events", [this](const httplib::Request&, httplib::Response& res) {
        if (streams.fetch_add(1) >= kMaxStreams) {
            --streams;
            refuse(res, 503,
                   fmt::format("too many pages: {} are open already (close one)", kMaxStreams));
            return;
        }
        page_seen.store(true);
        // what this stream has sent
        struct Sent {
            std::uint64_t scene = 0, frame = 0, message = 0, simulations = 0;
            bool hello = false;
            bool counted = true;
        };
        auto sent_state = std::make_shared<Sent>();
        res.set_header("Cache-Control", "no-cache");
        res.set_header("X-Accel-Buffering", "no");
        res.set_chunked_content_provider(
            "text/event-stream",
            [this, sent_state](std::size_t, httplib::DataSink& sink) {
                Sent& s = *sent_state;
                std::string out;
                if (!s.hello) {
                    s.hello = true;
                    out += "retry: 1000\n\n";
                }
                {
                    std::unique_lock<std::mutex> lock(mutex);
                    const auto fresh = [&] {
                        return stopping || scene_version != s.scene || frame_version != s.frame ||
                               message_version != s.message || simulations_version != s.simulations;
                    };
                    if (out.empty() &&
                        !changed.wait_for(lock, std::chrono::duration<double>(kHeartbeatSeconds),
                                          fresh)) {
                        out += ": still here\n\n";  // a heartbeat finds a page that went away
                    }
                    if (stopping) return false;
                    if (simulations_version != s.simulations) {
                        s.simulations = simulations_version;
                        if (!simulations_json.empty()) out += sse("simulations", simulations_json);
                    }
                    if (scene_version != s.scene) {
                        s.scene = scene_version;
                        if (scene) out += *scene;
                    }
                    for (const auto& [n, text] : messages) {
                        if (n > s.message) out += text;
                    }
                    s.message = message_version;
                    if (frame_version != s.frame) {
                        s.frame = frame_version;
                        if (auto f = frame_text(lock)) {
                            out += *f;
                            ++sent;
                        }
                    }
                }
                // written outside the lock: a slow page holds up only its own thread
                if (!out.empty() && !sink.write(out.data(), out.size())) {
                    ++dropped;
                    return false;
                }
                return true;
            },
            [this, sent_state](bool) {
                if (sent_state->counted) {
                    sent_state->counted = false;
                    --streams;
                }
            });
    });

    http.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;  // a handler said why already
        if (res.status == 404) {
            ++refused;
            res.set_content(json_error(fmt::format("no such page: {} {} (the viewer serves /, "
                                                   "/api/events, /api/scene, /api/simulations, "
                                                   "/api/live, /api/world, /api/status and POST "
                                                   "/api/command)",
                                                   req.method, req.path.substr(0, 80))),
                            "application/json");
        } else if (res.status == 413) {
            ++refused;
            res.set_content(
                json_error(fmt::format("a request is at most {} bytes", kMaxWorldBytes)),
                "application/json");
        } else {
            ++refused;
            res.set_content(json_error(fmt::format("request refused (HTTP {})", res.status)),
                            "application/json");
        }
    });
    http.set_exception_handler(
        [this](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
            std::string what = "unknown error";
            try {
                std::rethrow_exception(ep);
            } catch (const std::exception& e) {
                what = e.what();
            } catch (...) {
            }
            refuse(res, 500, "internal error: " + what);
        });
}

Server::Server(ServerOptions options) : state_(std::make_shared<State>()) {
    State& s = *state_;
    if (options.host.empty()) throw ServerError("--host: an address expected");
    if (options.port < 0 || options.port > 65535) {
        throw ServerError(
            fmt::format("--port: a port number in [1, 65535] expected (got {})", options.port));
    }
    if (options.token.empty() && !is_loopback(options.host)) options.token = random_token();
    s.options = options;
    s.http.new_task_queue = [] { return new GrowingPool(); };
    s.http.set_payload_max_length(kMaxWorldBytes);
    s.http.set_keep_alive_max_count(1000);
    s.http.set_keep_alive_timeout(5);
    s.http.set_read_timeout(kReadTimeoutSeconds, 0);
    const double wt = std::max(0.05, options.write_timeout);
    s.http.set_write_timeout(static_cast<time_t>(wt),
                             static_cast<time_t>((wt - std::floor(wt)) * 1e6));
    s.http.set_tcp_nodelay(true);
    // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, with which a second viewer
    // on the same port would start and share the first one's connections
    // (the listening socket is the one this is called for, before it is bound)
    s.http.set_socket_options([state = &s](socket_t sock) {
        const int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        state->listening = sock;
    });
    s.routes();
    // the address may be a name: cpp-httplib resolves it; IPv6 literals come without brackets
    std::string bind_host = options.host;
    if (bind_host.size() > 2 && bind_host.front() == '[' && bind_host.back() == ']') {
        bind_host = bind_host.substr(1, bind_host.size() - 2);
    }
    bool ok = false;
    if (options.port == 0) {
        s.port = s.http.bind_to_any_port(bind_host);
        ok = s.port > 0;
    } else {
        ok = s.http.bind_to_port(bind_host, options.port);
        s.port = options.port;
    }
    if (!ok) {
        throw ServerError(fmt::format("cannot serve the viewer on {}:{}: {}", options.host,
                                      options.port, bind_failure(bind_host, options.port)));
    }
    // cpp-httplib listens with a backlog of 5: a burst of connections beyond the threads
    // taking them had its handshakes dropped, and a page's request waited a second for its SYN
    // to be sent again. Listening again on the bound socket sets the backlog (Linux).
    if (s.listening >= 0) ::listen(s.listening, SOMAXCONN);
    const std::string p = std::to_string(s.port);
    s.hosts = {"127.0.0.1:" + p, "localhost:" + p, "[::1]:" + p};
    if (!options.host.empty()) s.hosts.push_back(options.host + ":" + p);
    // the server's threads take no signals: a write to a page that went away fails with EPIPE
    // instead of raising SIGPIPE (cpp-httplib sends without MSG_NOSIGNAL), and Ctrl-C goes to
    // the program's own threads. They inherit this thread's mask, the pool from the listener.
    sigset_t quiet, old;
    sigemptyset(&quiet);
    for (int sig : {SIGPIPE, SIGINT, SIGTERM, SIGHUP})
        sigaddset(&quiet, sig);
    pthread_sigmask(SIG_BLOCK, &quiet, &old);
    s.thread = std::thread([&s] { s.http.listen_after_bind(); });
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    // httplib's stop() does nothing before the listener runs, which would leave a server stopped
    // at once (a port taken, a test) blocked in accept() forever: wait until it runs.
    while (!s.http.is_running())
        std::this_thread::sleep_for(std::chrono::microseconds(100));
}

Server::~Server() {
    stop();
}

void Server::stop() {
    State& s = *state_;
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        if (s.stopped) return;
        s.stopped = true;
        s.stopping = true;
    }
    s.changed.notify_all();
    s.http.stop();
    if (s.thread.joinable()) s.thread.join();
    std::lock_guard<std::mutex> lock(s.live_mutex);
    s.live = nullptr;
    s.run = nullptr;
    s.world = nullptr;
}

void Server::set_live_provider(LiveProvider fn) {
    std::lock_guard<std::mutex> lock(state_->live_mutex);
    state_->live = std::move(fn);
}

void Server::set_run_provider(RunProvider fn) {
    {
        std::lock_guard<std::mutex> lock(state_->mutex);
        state_->seekable = static_cast<bool>(fn);
    }
    std::lock_guard<std::mutex> lock(state_->live_mutex);
    state_->run = std::move(fn);
}

void Server::set_world_provider(WorldProvider fn) {
    std::lock_guard<std::mutex> lock(state_->live_mutex);
    state_->world = std::move(fn);
}

int Server::port() const {
    return state_->port;
}

const std::string& Server::token() const {
    return state_->options.token;
}

std::string Server::url() const {
    const State& s = *state_;
    std::string host = s.options.host;
    if (host == "0.0.0.0" || host == "::") host = "127.0.0.1";
    if (host.find(':') != std::string::npos && host.front() != '[') host = "[" + host + "]";
    std::string u = fmt::format("http://{}:{}/", host, s.port);
    if (!s.options.token.empty()) u += "?token=" + s.options.token;
    return u;
}

void Server::publish_scene(std::string json_text, std::vector<ParamControl> controls,
                           std::vector<std::string> sensors) {
    State& s = *state_;
    auto event = std::make_shared<const std::string>(sse("scene", json_text));
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.scene = std::move(event);
        s.controls = std::move(controls);
        s.sensors = std::move(sensors);
        ++s.scene_version;
    }
    s.changed.notify_all();
}

void Server::publish_simulations(std::string json_text, std::vector<int> simulations) {
    State& s = *state_;
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.simulations_json = std::move(json_text);
        s.simulation_numbers = std::move(simulations);
        ++s.simulations_version;
    }
    s.changed.notify_all();
}

void Server::publish_frame(Frame frame) {
    State& s = *state_;
    auto f = std::make_shared<const Frame>(std::move(frame));
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.frame = std::move(f);
        s.frame_event.reset();
        ++s.frame_version;
    }
    ++s.frames;
    s.changed.notify_all();
}

void Server::publish_message(const std::string& level, const std::string& text) {
    State& s = *state_;
    const std::string event = sse("message", json{{"level", level}, {"text", text}}.dump(
                                                 -1, ' ', false, json::error_handler_t::replace));
    {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.messages.emplace_back(++s.message_version, event);
        while (s.messages.size() > kMaxMessages)
            s.messages.pop_front();
    }
    s.changed.notify_all();
}

std::vector<Command> Server::take_commands() {
    State& s = *state_;
    std::lock_guard<std::mutex> lock(s.command_mutex);
    std::vector<Command> out(s.commands.begin(), s.commands.end());
    s.commands.clear();
    s.pending.store(false, std::memory_order_release);
    return out;
}

bool Server::has_commands() const {
    return state_->pending.load(std::memory_order_acquire);
}

void Server::wait_for_commands(double seconds) {
    State& s = *state_;
    if (!(seconds > 0)) return;
    std::unique_lock<std::mutex> lock(s.command_mutex);
    s.command_arrived.wait_for(lock, std::chrono::duration<double>(std::min(seconds, 3600.0)),
                               [&] { return !s.commands.empty(); });
}

bool Server::page_seen() const {
    return state_->page_seen.load();
}

ServerStats Server::stats() const {
    const State& s = *state_;
    ServerStats st;
    st.frames = s.frames.load();
    st.sent = s.sent.load();
    st.streams = s.streams.load();
    st.dropped = s.dropped.load();
    st.commands = s.accepted.load();
    st.refused = s.refused.load();
    return st;
}

}  // namespace gaitlab::viewer
