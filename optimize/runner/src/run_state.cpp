// OUT/state.json of an optimization run (see run_state.h).
#include "run_state.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gaitlab/error.h"
#include "results.h"

namespace gaitlab::optimize::detail {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gaitlab-optimize-run";
constexpr int kVersion = 1;

}  // namespace

std::string read_text_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(fmt::format("{}: cannot read", path.string()));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_run_state(const fs::path& out, const RunState& state) {
    nlohmann::ordered_json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    j["spec_file"] = state.spec_file;
    j["spec_text"] = state.spec_text;
    j["method"] = state.method;
    j["population"] = state.population;
    j["generations"] = state.generations;
    j["seed"] = state.seed;
    j["command"] = state.command;
    j["first_population"] = state.first_population;
    j["generation"] = state.generation;
    j["jsonl_bytes"] = state.jsonl_bytes;
    j["wall"] = state.wall;
    j["method_state"] = nlohmann::ordered_json::parse(state.method_state);
    const std::string text =
        j.dump(1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
    const fs::path path = out / "state.json";
    const fs::path tmp = out / "state.json.tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        throw IoError(fmt::format("{}: cannot write: {}", tmp.string(), std::strerror(errno)));
    }
    const bool ok = write_all(fd, text) && ::fsync(fd) == 0;
    const int saved = errno;
    ::close(fd);
    std::error_code ec;
    if (!ok) {
        fs::remove(tmp, ec);  // no cut or empty temporary file left on a full disk
        throw IoError(fmt::format("{}: cannot write: {}", tmp.string(), std::strerror(saved)));
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw IoError(fmt::format("{}: cannot write: {}", path.string(), ec.message()));
    }
}

RunState read_run_state(const fs::path& out) {
    const fs::path path = out / "state.json";
    std::error_code ec;
    if (!fs::is_directory(out, ec)) {
        throw SpecError(
            fmt::format("--resume: --out {}: no such folder (the results folder of "
                        "the run to resume expected)",
                        out.string()));
    }
    if (!fs::exists(path, ec)) {
        throw SpecError(fmt::format(
            "--resume: {}: missing (not the results folder of a gaitlab optimize run, or one "
            "made before runs could be resumed)",
            path.string()));
    }
    const std::string where = path.string();
    nlohmann::ordered_json j;
    try {
        j = nlohmann::ordered_json::parse(read_text_file(path));
    } catch (const nlohmann::json::exception& e) {
        throw SpecError(fmt::format("--resume: {}: not a run state: {}", where, e.what()));
    }
    const auto field = [&](const char* name) -> const nlohmann::ordered_json& {
        if (!j.is_object() || !j.contains(name)) {
            throw SpecError(
                fmt::format("--resume: {}: not a run state: '{}' missing", where, name));
        }
        return j.at(name);
    };
    try {
        if (field("format") != kFormat) {
            throw SpecError(
                fmt::format("--resume: {}: not a run state: 'format' is {} "
                            "(expected \"{}\")",
                            where, field("format").dump(), kFormat));
        }
        if (field("version") != kVersion) {
            throw SpecError(fmt::format("--resume: {}: 'version' {} is not known (expected {})",
                                        where, field("version").dump(), kVersion));
        }
        RunState s;
        s.spec_file = field("spec_file").get<std::string>();
        s.spec_text = field("spec_text").get<std::string>();
        s.method = field("method").get<std::string>();
        s.population = field("population").get<int>();
        s.generations = field("generations").get<int>();
        s.seed = field("seed").get<std::uint64_t>();
        s.command = field("command").get<std::string>();
        s.first_population = field("first_population").get<int>();
        s.generation = field("generation").get<int>();
        s.jsonl_bytes = field("jsonl_bytes").get<std::uint64_t>();
        s.wall = field("wall").get<double>();
        s.method_state = field("method_state").dump();
        return s;
    } catch (const nlohmann::json::exception& e) {
        throw SpecError(fmt::format("--resume: {}: not a run state: {}", where, e.what()));
    }
}

void check_resumable(const RunState& saved, const RunState& now, const fs::path& out) {
    if (saved.spec_text != now.spec_text) {
        throw SpecError(
            fmt::format("--resume: {} is not the spec the run in {} began with ({}): the spec file "
                        "changed, or is another one (its text then is in {}/state.json)",
                        now.spec_file, out.string(), saved.spec_file, out.string()));
    }
    const auto differs = [&](const char* option, const std::string& was, const std::string& is) {
        if (was == is) return;
        throw SpecError(
            fmt::format("--resume: {} {} differs from the run in {} ({} {}): resume "
                        "with the options the run began with",
                        option, is, out.string(), option, was));
    };
    differs("--method", saved.method, now.method);
    differs("--population", saved.population > 0 ? std::to_string(saved.population) : "default",
            now.population > 0 ? std::to_string(now.population) : "default");
    differs("--generations", std::to_string(saved.generations), std::to_string(now.generations));
    differs("--seed", std::to_string(saved.seed), std::to_string(now.seed));
}

}  // namespace gaitlab::optimize::detail
