// The results folder's shared pieces, and the parts of an optimization's results written at
// its end besides best.json: the convergence plot and the best individual's run (see results.h).
#include "results.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
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

void open_results_folder(const std::string& out) {
    std::error_code ec;
    if (fs::exists(out, ec)) {
        if (!fs::is_directory(out, ec)) {
            throw SpecError(fmt::format("--out {}: exists and is not a folder", out));
        }
        if (!fs::is_empty(out, ec)) {
            throw SpecError(fmt::format(
                "--out {}: the folder exists and is not empty (an earlier run's results are "
                "kept: choose another folder)",
                out));
        }
    }
    fs::create_directories(out, ec);
    if (ec) throw IoError(fmt::format("{}: cannot create the folder: {}", out, ec.message()));
}

nlohmann::ordered_json parameters_json(const Spec& spec, const std::vector<double>& x) {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (size_t i = 0; i < x.size(); ++i) {
        if (spec.parameters[i].integer) {
            j[spec.parameters[i].name] = static_cast<long long>(x[i]);
        } else {
            j[spec.parameters[i].name] = x[i];
        }
    }
    return j;
}

nlohmann::ordered_json fitness_json(double f) {
    return std::isfinite(f) ? nlohmann::ordered_json(f) : nlohmann::ordered_json(nullptr);
}

std::string evaluation_line(const Spec& spec, int generation, std::size_t individual,
                            const std::vector<double>& x, const Evaluation& ev) {
    nlohmann::ordered_json j;
    j["generation"] = generation;
    j["individual"] = individual;
    j["parameters"] = parameters_json(spec, x);
    j["fitness"] = fitness_json(ev.failed() ? std::nan("") : ev.fitness);
    j["seconds"] = ev.seconds;
    j["worker"] = ev.worker;
    if (ev.rank >= 0) j["rank"] = ev.rank;  // under MPI: the rank that evaluated it
    if (ev.failed()) j["error"] = ev.error;
    return json_text(j, -1) + "\n";
}

std::string json_text(const nlohmann::ordered_json& j, int indent) {
    return j.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string reason(int error) {
    return error == 0 ? std::string() : fmt::format(": {}", std::strerror(error));
}

bool write_all(int fd, const std::string& text) {
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return false;
        if (n == 0) {  // no progress and no error: say so rather than loop
            errno = EIO;
            return false;
        }
        done += static_cast<size_t>(n);
    }
    return true;
}

void write_file(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(fmt::format("{}: cannot write{}", tmp, reason(errno)));
    bool ok = write_all(fd, text);
    int error = ok ? 0 : errno;
    if (::close(fd) != 0 && ok) {  // some file systems report a full disk only here
        ok = false;
        error = errno;
    }
    std::error_code ec;
    if (!ok) {
        fs::remove(tmp, ec);  // a full disk must not keep a cut or empty temporary file
        throw IoError(fmt::format("{}: cannot write{}", tmp, reason(error)));
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw IoError(fmt::format("{}: cannot write: {}", path, ec.message()));
    }
}

void append_text(std::ofstream& out, const fs::path& path, const std::string& text) {
    errno = 0;  // the stream sets it when the write under it fails
    out << text;
    out.flush();
    if (!out) throw IoError(fmt::format("{}: cannot write{}", path.string(), reason(errno)));
}

std::string plot_convergence(const fs::path& out, const std::string& title,
                             const std::string& fitness) {
    const fs::path jsonl = out / "evaluations.jsonl";
    std::ifstream in(jsonl, std::ios::binary);
    if (!in) return fmt::format("{}: cannot read", jsonl.string());
    // per generation: its successful fitness values and the best of them
    struct Generation {
        std::vector<double> values;
        double best = -std::numeric_limits<double>::infinity();
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
                g.values.push_back(v);
                g.best = std::max(g.best, v);
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
        const auto n = static_cast<double>(g.values.size());
        if (n > 0 && !(g.best <= best)) best = g.best;
        // each value divided before they are added, as the run's progress line does: values
        // near the largest double made the sum infinite
        double mean = n > 0 ? 0 : nan;
        for (const double v : g.values)
            mean += v / n;
        t.rows.push_back({static_cast<double>(number + 1), best, mean});
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
