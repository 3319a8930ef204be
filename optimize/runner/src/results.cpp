// The results folder's shared pieces (see results.h).
#include "results.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "gaitlab/error.h"

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

void write_file(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) throw IoError(fmt::format("{}: cannot write", tmp));
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw IoError(fmt::format("{}: cannot write: {}", path, ec.message()));
}

}  // namespace gaitlab::optimize::detail
