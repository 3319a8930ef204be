// What serving the viewer costs the simulation (issue 12 wants at most 5% of throughput): the
// same script (an 8-module pitch-pitch snake with a sine wave, as fast as possible) run by a
// plain Lua host, then under a View with 0, 1 and 4 pages reading its event stream. Reports the
// wall time and the simulation thread's CPU time per simulated second, median of N interleaved
// runs, and the overhead against the plain host. The page's clients are cpp-httplib clients on
// loopback that read every frame, as a browser would.
//
//   viewer_bench [--quick]
//   viewer_bench one PAGES SECONDS    one run (PAGES -1: no viewer), for callgrind
//                                     (--separate-threads=yes: thread 1 is the simulation's)
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/viewer/view.h"

namespace {

const char* kScript = R"(
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local sim = gaitlab.simulation{ world = world }
sim.speed = math.huge
sim:run(SECONDS)
)";

double thread_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct Sample {
    double wall = 0, cpu = 0;
    unsigned long long frames = 0, sent = 0;
};

// one run: -1 pages: no view at all
Sample run(int pages, double seconds) {
    std::string script = kScript;
    script.replace(script.find("SECONDS"), 7, std::to_string(seconds));
    gaitlab::scripting::LuaHost host;
    std::unique_ptr<gaitlab::viewer::View> view;
    std::atomic<bool> stop{false};
    std::vector<std::thread> clients;
    if (pages >= 0) {
        gaitlab::viewer::ViewOptions o;
        o.wait_for_page = false;
        view = std::make_unique<gaitlab::viewer::View>(host, gaitlab::viewer::ServerOptions{}, o);
        const int port = view->server().port();
        for (int i = 0; i < pages; ++i) {
            clients.emplace_back([port, &stop] {
                httplib::Client c("127.0.0.1", port);
                c.Get("/api/events", [&stop](const char*, size_t) { return !stop.load(); });
            });
        }
        while (view->server().stats().streams < pages)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    Sample s;
    const auto start = std::chrono::steady_clock::now();
    const double cpu = thread_cpu();
    host.run_string(script, "bench");
    s.cpu = thread_cpu() - cpu;
    s.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (view) {
        s.frames = view->server().stats().frames;
        s.sent = view->server().stats().sent;
        stop = true;
        view->message("info", "done");  // wakes the streams so they see `stop`
    }
    for (auto& c : clients)
        c.join();
    return s;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 4 && std::strcmp(argv[1], "one") == 0) {
        const Sample s = run(std::atoi(argv[2]), std::atof(argv[3]));
        std::printf("wall %.3f s, simulation thread CPU %.3f s, frames %llu, sent %llu\n", s.wall,
                    s.cpu, s.frames, s.sent);
        return 0;
    }
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const double seconds = quick ? 10 : 30;
    const int reps = quick ? 3 : 5;
    const std::vector<int> configs = {-1, 0, 1, 4};
    std::vector<std::vector<Sample>> samples(configs.size());
    for (int r = 0; r < reps; ++r) {
        for (size_t c = 0; c < configs.size(); ++c)
            samples[c].push_back(run(configs[c], seconds));
    }
    std::printf(
        "\n### Serving the viewer (%g simulated s as fast as possible, median of %d "
        "interleaved runs)\n\n",
        seconds, reps);
    std::printf(
        "| setup | wall ms per simulated s | overhead | simulation thread CPU ms per "
        "simulated s | overhead | frames published | frames sent |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    double base_wall = 0, base_cpu = 0;
    for (size_t c = 0; c < configs.size(); ++c) {
        std::vector<double> wall, cpu, frames, sent;
        for (const Sample& s : samples[c]) {
            wall.push_back(s.wall / seconds * 1e3);
            cpu.push_back(s.cpu / seconds * 1e3);
            frames.push_back(static_cast<double>(s.frames));
            sent.push_back(static_cast<double>(s.sent));
        }
        const double w = median(wall), u = median(cpu);
        if (c == 0) {
            base_wall = w;
            base_cpu = u;
        }
        const std::string name = configs[c] < 0    ? "no viewer"
                                 : configs[c] == 0 ? "viewer, no page"
                                                   : "viewer, " + std::to_string(configs[c]) +
                                                         (configs[c] == 1 ? " page" : " pages");
        std::printf("| %s | %.2f | %+.1f%% | %.2f | %+.1f%% | %.0f | %.0f |\n", name.c_str(), w,
                    100 * (w / base_wall - 1), u, 100 * (u / base_cpu - 1), median(frames),
                    median(sent));
    }
    return 0;
}
