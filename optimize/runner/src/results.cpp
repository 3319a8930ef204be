// The convergence plot and the best individual's recorded run (see results.h).
#include "results.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/scripting/lua_host.h"

namespace gaitlab::optimize::detail {

namespace fs = std::filesystem;

std::string plot_convergence(const fs::path& out, const std::string& title,
                             const std::string& fitness) {
    const fs::path jsonl = out / "evaluations.jsonl";
    std::ifstream in(jsonl, std::ios::binary);
    if (!in) return fmt::format("{}: cannot read", jsonl.string());
    // per generation: the sum and number of its successful fitness values
    struct Generation {
        double sum = 0, best = -std::numeric_limits<double>::infinity();
        int ok = 0;
    };
    std::map<long, Generation> generations;
    long line_number = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_number;
        try {
            const nlohmann::json j = nlohmann::json::parse(line);
            Generation& g = generations[j.at("generation").get<long>()];
            const nlohmann::json& f = j.at("fitness");
            if (f.is_number()) {
                const double v = f.get<double>();
                g.sum += v;
                g.best = std::max(g.best, v);
                ++g.ok;
            }
        } catch (const nlohmann::json::exception& e) {
            return fmt::format("{}:{}: {}", jsonl.string(), line_number, e.what());
        }
    }
    TablePlot t;
    t.output = (out / "convergence.png").string();
    t.title = title;
    t.xlabel = "generation";
    t.ylabel = fitness;
    t.columns = {"generation", "best so far", "generation mean"};
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double best = nan;
    for (const auto& [number, g] : generations) {
        if (g.ok > 0 && !(g.best <= best)) best = g.best;
        t.rows.push_back({static_cast<double>(number + 1), best, g.ok > 0 ? g.sum / g.ok : nan});
    }
    try {
        plot_table(t);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::string record_run(const std::string& simulation, const fs::path& dir,
                       const std::string& command) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    if (ec) return fmt::format("{}: cannot replace: {}", dir.string(), ec.message());
    scripting::LuaHost host;
    scripting::RecordSettings rec;
    rec.by_default = true;
    rec.dir = dir.string();
    rec.name = fs::path(simulation).stem().string();
    rec.script = simulation;
    rec.command = command;
    host.set_recording(rec);
    host.set_print(false);
    host.set_reporter([](const std::string&) {});
    host.seed(0);
    host.set_args(simulation, {});
    std::string error;
    try {
        host.run_simulation_file(simulation);
    } catch (const std::exception& e) {
        error = e.what();
    }
    try {
        host.finish(error);
    } catch (const std::exception& e) {
        if (error.empty()) error = e.what();
    }
    return error;
}

}  // namespace gaitlab::optimize::detail
