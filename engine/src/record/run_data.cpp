#include "gaitlab/run_data.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "formats/csv.h"
#include "formats/json.h"
#include "formats/run_files.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "gaitlab/suggest.h"

namespace gaitlab {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// "cannot read PATH: REASON"
[[noreturn]] void cannot_read(const std::string& path, const std::string& reason) {
    throw IoError(fmt::format("cannot read {}: {}", path, reason));
}

// a file of the run folder itself: not a link (which could lead anywhere), a FIFO or a device
void check_own_file(const std::string& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) cannot_read(path, formats::reason(errno));
    if (S_ISLNK(st.st_mode)) {
        cannot_read(path, "a symbolic link (the files of a run folder must be its own)");
    }
    if (S_ISDIR(st.st_mode)) cannot_read(path, "is a directory");
    if (!S_ISREG(st.st_mode)) cannot_read(path, "not a regular file (a FIFO, device or socket)");
}

// a whole file of the run folder (run.json, log.txt), at most kMaxInputBytes
std::string read_own_file(const std::string& path) {
    check_own_file(path);
    return read_file(path);
}

// complete lines of a file of the run folder, one at a time, each at most kMaxLineBytes long;
// a last line without its line end is dropped and remembered as truncated. The file is opened
// without following a link and without waiting for a FIFO's writer, and must be a regular file
class LineReader {
  public:
    explicit LineReader(const std::string& path) : path_(path) {
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOFOLLOW);
        if (fd_ < 0) {
            const int e = errno;
            if (e == ELOOP) check_own_file(path);  // says it is a link
            cannot_read(path, formats::reason(e));
        }
        struct stat st {};
        if (::fstat(fd_, &st) != 0) fail_read(errno);
        if (S_ISDIR(st.st_mode)) fail_read("is a directory");
        if (!S_ISREG(st.st_mode)) fail_read("not a regular file (a FIFO, device or socket)");
        const int flags = ::fcntl(fd_, F_GETFL);
        if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
    }
    ~LineReader() {
        if (fd_ >= 0) ::close(fd_);
    }
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    // the next complete line, without its line end; valid until the next call
    bool next(std::string_view& line) {
        for (;;) {
            const char* start = buf_.data() + pos_;
            const size_t avail = buf_.size() - pos_;
            if (const void* nl = std::memchr(start, '\n', avail)) {
                size_t len = static_cast<size_t>(static_cast<const char*>(nl) - start);
                pos_ += len + 1;
                ++number_;
                if (len > kMaxLineBytes) too_long();
                if (len > 0 && start[len - 1] == '\r') --len;
                line = std::string_view(start, len);
                return true;
            }
            if (avail > kMaxLineBytes) {
                ++number_;
                too_long();
            }
            if (eof_) {
                truncated_ = avail > 0;
                return false;
            }
            buf_.erase(0, pos_);
            pos_ = 0;
            const size_t old = buf_.size();
            buf_.resize(old + kChunk);
            ssize_t n = 0;
            do {
                n = ::read(fd_, buf_.data() + old, kChunk);
            } while (n < 0 && errno == EINTR);
            if (n < 0) {
                buf_.resize(old);
                fail_read(errno);
            }
            buf_.resize(old + static_cast<size_t>(n));
            eof_ = n == 0;
        }
    }
    // the next CSV record: a line, or several when a quoted field holds line ends (RFC 4180:
    // a record goes on while its quotes are open); its first line is record_line()
    bool next_record(std::string& record) {
        std::string_view line;
        if (!next(line)) return false;
        record_line_ = number_;
        record.assign(line);
        while (std::count(record.begin(), record.end(), '"') % 2 != 0) {
            if (!next(line)) {  // cut short inside a quoted field
                unterminated_ = true;
                return false;
            }
            if (record.size() + line.size() > kMaxLineBytes) too_long();
            record += '\n';
            record.append(line);
        }
        return true;
    }
    long number() const { return number_; }
    long record_line() const { return record_line_; }
    // whether the file ended inside a quoted field: the last record (from record_line()) has a
    // '"' that never closes
    bool unterminated() const { return unterminated_; }
    bool truncated() const { return truncated_; }
    const std::string& path() const { return path_; }

  private:
    static constexpr size_t kChunk = size_t{1} << 16;
    [[noreturn]] void fail_read(int e) const { cannot_read(path_, formats::reason(e)); }
    [[noreturn]] void fail_read(const char* why) const { cannot_read(path_, why); }
    [[noreturn]] void too_long() const {
        throw FormatError(fmt::format("{}:{}: line longer than the {} gaitlab reads", path_,
                                      number_, describe_size(kMaxLineBytes)),
                          path_, static_cast<int>(number_));
    }

    std::string path_;
    int fd_ = -1;
    bool unterminated_ = false;
    std::string buf_;
    size_t pos_ = 0;
    long number_ = 0;
    long record_line_ = 0;
    bool eof_ = false;
    bool truncated_ = false;
};

// the numbers of columns `wanted` (ascending) of a data line with `fields` fields
void parse_row(const LineReader& r, std::string_view line, size_t fields,
               const std::vector<size_t>& wanted, double* out,
               const std::vector<std::string>& header) {
    size_t column = 0, start = 0, w = 0;
    for (size_t i = 0; i <= line.size(); ++i) {
        if (i < line.size() && line[i] != ',') continue;
        if (w < wanted.size() && wanted[w] == column) {
            const std::string_view text = line.substr(start, i - start);
            if (!formats::parse_number(text, out[w])) {
                throw FormatError(fmt::format("{}:{}: column '{}': number expected, got '{}'",
                                              r.path(), r.number(), header[column], text));
            }
            ++w;
        }
        ++column;
        start = i + 1;
    }
    if (column != fields) {
        throw FormatError(
            fmt::format("{}:{}: {} fields expected, got {}", r.path(), r.number(), fields, column));
    }
}

SeriesInfo series_from(const std::vector<std::string>& f, const std::string& where) {
    SeriesInfo s;
    s.name = f[0];
    if (!parse_series_kind(f[1], s.kind)) {
        throw FormatError(
            fmt::format("{}: kind 'robot', 'controller', 'sensor' or 'object' expected, got "
                        "'{}'",
                        where, f[1]));
    }
    s.source = f[2];
    s.value = f[3];
    if (!f[4].empty()) {
        char* end = nullptr;
        const long j = std::strtol(f[4].c_str(), &end, 10);
        if (*end != '\0' || j < 1 || j > 1000000) {
            throw FormatError(fmt::format(
                "{}: joint number (1, 2, ...) or nothing expected, got '{}'", where, f[4]));
        }
        s.joint = static_cast<int>(j);
    }
    s.body = f[5];
    s.unit = f[6];
    return s;
}

// "a/b.lua" inside config/: not empty, not absolute, no ".." that leaves it
bool inside_config(const std::string& path) {
    if (path.empty() || path.find('\0') != std::string::npos) return false;
    const fs::path p = fs::path(path).lexically_normal();
    return !p.empty() && !p.is_absolute() && *p.begin() != ".." && *p.begin() != ".";
}

// what run.json says, each value checked: a folder from elsewhere may say anything
class MetaReader {
  public:
    explicit MetaReader(const formats::JsonDocument& doc) : doc_(doc) {}

    [[noreturn]] void fail(const json& at, const std::string& what) const {
        const int line = doc_.line(at);
        throw FormatError(fmt::format("{}:{}: {}", doc_.file(), line, what), doc_.file(), line);
    }
    // a number member (or `fallback` when it is absent)
    double number(const json& o, const char* key, const char* name, double fallback) const {
        const json* v = formats::find(o, key);
        if (!v) return fallback;
        if (!v->is_number()) fail(*v, fmt::format("{}: a number expected", name));
        return v->get<double>();
    }
    // a whole number member in [lo, hi]
    long long integer(const json& o, const char* key, const char* name, long long fallback,
                      long long lo, long long hi) const {
        const json* v = formats::find(o, key);
        if (!v) return fallback;
        const std::optional<long long> x = formats::as_integer(*v);
        if (!x || *x < lo || *x > hi) {
            fail(*v, fmt::format("{}: a whole number from {} to {} expected", name, lo, hi));
        }
        return *x;
    }
    // a config path member, which must stay inside config/ ("" only if `may_be_empty`)
    std::string config_path(const json& o, const char* key, const char* name,
                            bool may_be_empty = false) const {
        const json* v = formats::find(o, key);
        if (!v) return "";
        const std::string p = formats::as_string(*v);
        if (p.empty() && may_be_empty && v->is_string()) return p;
        if (!inside_config(p)) {
            fail(*v, fmt::format("{}: a path inside config/ expected, got '{}'", name, p));
        }
        return p;
    }
    // the members of an object in the order the file has them (the parsed object sorts them)
    std::vector<std::pair<std::string, const json*>> members(const json& o) const {
        std::vector<std::pair<std::string, const json*>> out;
        if (!o.is_object()) return out;
        for (auto it = o.begin(); it != o.end(); ++it)
            out.emplace_back(it.key(), &it.value());
        std::stable_sort(out.begin(), out.end(), [&](const auto& a, const auto& b) {
            return doc_.line(*a.second) < doc_.line(*b.second);
        });
        return out;
    }

    // a true/false member (`fallback` when it is absent)
    bool boolean(const json& o, const char* key, const char* name, bool fallback) const {
        const json* v = formats::find(o, key);
        if (!v) return fallback;
        if (!v->is_boolean()) fail(*v, fmt::format("{}: true or false expected", name));
        return v->get<bool>();
    }

  private:
    const formats::JsonDocument& doc_;
};

RunMeta meta_from(const formats::JsonDocument& doc) {
    const json& j = doc.root();
    const std::string& file = doc.file();
    if (!j.is_object() || formats::str_at(j, "format") != "gaitlab run") {
        throw FormatError(fmt::format(
            "{}:1: not a gaitlab run description (an object with \"format\": \"gaitlab run\" "
            "expected)",
            file));
    }
    constexpr long long kMaxInt = 2147483647;
    constexpr long long kMaxTick = 9000000000000000000;
    const MetaReader r(doc);
    RunMeta m;
    m.name = formats::str_at(j, "name");
    m.status = formats::str_at(j, "status");
    m.message = formats::str_at(j, "message");
    m.recording_failed = r.boolean(j, "recording_failed", "recording_failed", false);
    m.started = formats::str_at(j, "started");
    m.ended = formats::str_at(j, "ended");
    m.first_tick = static_cast<long>(r.integer(j, "first_tick", "first_tick", 0, 0, kMaxTick));
    m.last_tick = static_cast<long>(r.integer(j, "last_tick", "last_tick", -1, -1, kMaxTick));
    if (const json* p = formats::find(j, "process")) {
        m.process.pid = static_cast<long>(r.integer(*p, "pid", "process.pid", 0, 0, kMaxInt));
        m.process.host = formats::str_at(*p, "host");
        m.process.boot_id = formats::str_at(*p, "boot_id");
        if (const json* t = formats::find(*p, "start_time"))
            m.process.start_time = formats::as_uint(*t);
    }
    if (const json* s = formats::find(j, "simulation")) {
        m.simulation = static_cast<int>(r.integer(*s, "index", "simulation.index", 1, 1, kMaxInt));
        m.options.dt = r.number(*s, "dt", "simulation.dt", m.options.dt);
        if (!(std::isfinite(m.options.dt) && m.options.dt > 0)) {
            r.fail(*formats::find(*s, "dt"),
                   "simulation.dt: a positive number of seconds expected");
        }
        m.options.control_every = static_cast<int>(
            r.integer(*s, "control_every", "simulation.control_every", 30, 1, kMaxInt));
        m.options.solver_iterations = static_cast<int>(
            r.integer(*s, "solver_iterations", "simulation.solver_iterations", 20, 1, kMaxInt));
        if (const json* seed = formats::find(*s, "seed")) m.options.seed = formats::as_uint(*seed);
        if (formats::str_at(*s, "on_controller_error") == "continue") {
            m.options.on_controller_error = ControllerErrorPolicy::continue_;
        }
        // recordings before the solver was written (and before block_nncg was the default)
        // ran pgs
        m.options.solver = ConstraintSolver::pgs;
        if (const json* solver = formats::find(*s, "solver")) {
            const std::string name = solver->is_string() ? solver->get<std::string>() : "";
            if (!parse_solver(name, m.options.solver)) {
                r.fail(*solver, "simulation.solver: " + solver_names() + " expected");
            }
        }
        // runs without Newton steps do not write them
        m.options.newton_steps = static_cast<int>(
            r.integer(*s, "newton_steps", "simulation.newton_steps", 0, 0, kMaxNewtonSteps));
    }
    if (const json* rec = formats::find(j, "recording")) {
        m.record_every = static_cast<int>(
            r.integer(*rec, "record_every", "recording.record_every", 0, 0, kMaxInt));
        m.flush_seconds = r.number(*rec, "flush_seconds", "recording.flush_seconds", 2);
        if (!(std::isfinite(m.flush_seconds) && m.flush_seconds >= 0)) {
            r.fail(*formats::find(*rec, "flush_seconds"),
                   "recording.flush_seconds: a non-negative number of seconds expected");
        }
        if (const json* sel = formats::find(*rec, "select"); sel && sel->is_array()) {
            for (const json& p : *sel)
                m.select.push_back(formats::as_string(p));
        }
    }
    if (const json* run = formats::find(j, "run")) {
        m.script = r.config_path(*run, "script", "run.script", true);
        if (const json* args = formats::find(*run, "args"); args && args->is_array()) {
            for (const json& a : *args)
                m.args.push_back(formats::as_string(a));
        }
        if (const json* seed = formats::find(*run, "seed")) m.script_seed = formats::as_uint(*seed);
        if (const json* by = formats::find(*run, "started_by")) {
            m.started_by = formats::as_string(*by, "simulation");
        }
    }
    if (const json* files = formats::find(j, "config"); files && files->is_array()) {
        for (const json& f : *files) {
            ConfigFile c;
            c.role = formats::str_at(f, "role");
            c.path = r.config_path(f, "path", "config[].path");
            c.origin = formats::str_at(f, "origin");
            c.of = formats::str_at(f, "of");
            if (const json* v = formats::find(f, "version")) c.version = formats::as_uint(*v);
            c.hash = formats::str_at(f, "hash");  // "" in folders written before gaitlab kept it
            m.files.push_back(std::move(c));
        }
    }
    if (const json* p = formats::find(j, "provenance")) {
        for (const auto& [k, v] : r.members(*p))
            m.provenance.emplace_back(k, formats::as_string(*v));
    }
    return m;
}

}  // namespace

RunMeta RunData::read_meta(const std::string& path) {
    const formats::JsonDocument doc(read_own_file(path), path);
    return meta_from(doc);
}

RunData::RunData(std::string dir) : dir_(std::move(dir)) {
    std::error_code ec;
    const fs::path p(dir_);
    if (!fs::exists(p, ec)) throw IoError(fmt::format("no run folder at {}", dir_));
    if (!fs::is_directory(p, ec)) {
        throw IoError(fmt::format("{} is not a run folder: it is not a folder", dir_));
    }
    std::vector<std::string> missing;
    for (const char* f : {"run.json", "series.csv", "data.csv"}) {
        if (!fs::exists(fs::symlink_status(p / f, ec))) missing.emplace_back(f);
    }
    if (!missing.empty()) {
        std::string list;
        for (size_t i = 0; i < missing.size(); ++i) {
            if (i > 0) list += i + 1 == missing.size() ? " and " : ", ";
            list += missing[i];
        }
        throw IoError(fmt::format(
            "{} is not a run folder: it has no {} (a run folder holds run.json, series.csv, "
            "data.csv, events.csv, log.txt and config/)",
            dir_, list));
    }
    meta_ = read_meta((p / "run.json").string());

    LineReader list((p / "series.csv").string());
    std::string record;
    std::vector<std::string> f;
    if (!list.next_record(record) || !formats::split_line(record, f) || f.size() != 7 ||
        f[0] != "name") {
        throw FormatError(fmt::format(
            "{}:1: header 'name,kind,source,value,joint,body,unit' expected", list.path()));
    }
    while (list.next_record(record)) {
        if (!formats::split_line(record, f) || f.size() != 7) {
            throw FormatError(
                fmt::format("{}:{}: 7 fields expected (name,kind,source,value,"
                            "joint,body,unit)",
                            list.path(), list.record_line()));
        }
        if (series_.size() == kMaxSeries) {
            throw FormatError(fmt::format("{}:{}: more than the {} series gaitlab reads",
                                          list.path(), list.record_line(), kMaxSeries));
        }
        series_.push_back(series_from(f, fmt::format("{}:{}", list.path(), list.record_line())));
        index_.emplace(series_.back().name, series_.size() - 1);  // the first of a name
    }
    // series.csv is written whole, never cut short: a quote that never closes is a broken
    // file here (it swallowed the lines after it, and data.csv was blamed)
    if (list.unterminated()) {
        throw FormatError(fmt::format("{}:{}: a quoted field that never ends (a '\"' without its "
                                      "closing '\"')",
                                      list.path(), list.record_line()),
                          list.path(), static_cast<int>(list.record_line()));
    }

    LineReader rows((p / "data.csv").string());
    if (!rows.next_record(record) || !formats::split_line(record, f) || f.empty() ||
        f[0] != "time") {
        throw FormatError(fmt::format("{}:1: header 'time,<series names>' expected", rows.path()));
    }
    if (f.size() != series_.size() + 1) {
        throw FormatError(
            fmt::format("{}:1: {} columns expected (time and the {} series of "
                        "series.csv), got {}",
                        rows.path(), series_.size() + 1, series_.size(), f.size()));
    }
    for (size_t i = 0; i < series_.size(); ++i) {
        if (f[i + 1] != series_[i].name) {
            throw FormatError(fmt::format("{}:1: column {} is '{}' where series.csv says '{}'",
                                          rows.path(), i + 2, f[i + 1], series_[i].name));
        }
    }
}

std::string RunData::state() const {
    const RunMeta& m = meta_;
    if (m.status == "running") {
        switch (liveness(m.process)) {
            case Liveness::alive:
                return fmt::format("running (still being written by process {})", m.process.pid);
            case Liveness::gone:
                return "incomplete (the process ended without closing it)";
            case Liveness::unknown:
                break;
        }
        if (m.process.pid > 0) {
            return fmt::format(
                "running on {} as process {}, or ended there without closing it (it cannot be "
                "checked from here)",
                m.process.host.empty() ? "another host" : m.process.host, m.process.pid);
        }
        return "incomplete or still running (run.json names no process)";
    }
    if (m.status == "interrupted") {
        return m.message.empty() ? "interrupted" : "interrupted by " + m.message;
    }
    return m.message.empty() ? m.status : m.status + ": " + m.message;
}

std::string RunData::config_file(const std::string& path) const {
    const std::string where = (fs::path(dir_) / "run.json").string();
    if (!inside_config(path)) {
        throw FormatError(
            fmt::format("{}: configuration file '{}' is not inside config/", where, path));
    }
    const fs::path config = fs::path(dir_) / "config";
    const fs::path file = config / fs::path(path).lexically_normal();
    // links inside config/ must not lead out of it either
    std::error_code ec1, ec2;
    const fs::path real_config = fs::weakly_canonical(config, ec1);
    const fs::path real_file = fs::weakly_canonical(file, ec2);
    const fs::path rel = real_file.lexically_relative(real_config);
    if (ec1 || ec2 || rel.empty() || *rel.begin() == "..") {
        throw FormatError(fmt::format(
            "{}: configuration file '{}' leads out of config/ (through a link)", where, path));
    }
    return file.string();
}

std::vector<std::string> RunData::names() const {
    std::vector<std::string> n;
    for (const SeriesInfo& s : series_)
        n.push_back(s.name);
    return n;
}

const SeriesInfo& RunData::find(std::string_view name) const {
    const auto it = index_.find(std::string(name));
    if (it != index_.end()) return series_[it->second];
    throw SpecError(fmt::format("unknown series '{}'{}", name, suggest(name, names())));
}

const SeriesInfo& RunData::find(SeriesKind kind, std::string_view value, int joint,
                                std::string_view source) const {
    std::vector<const SeriesInfo*> hits;
    for (const SeriesInfo& s : series_) {
        if (s.kind == kind && s.value == value && s.joint == joint &&
            (source.empty() || s.source == source))
            hits.push_back(&s);
    }
    const std::string what =
        fmt::format("{} series '{}'{}{}", to_string(kind), value,
                    joint > 0 ? fmt::format(" of joint {}", joint) : std::string(),
                    source.empty() ? std::string() : fmt::format(" from '{}'", source));
    if (hits.size() == 1) return *hits[0];
    if (hits.empty()) {
        // the value is there, but for other joints (or for none): say which, not "did you
        // mean" the same word
        std::vector<int> joints;
        for (const SeriesInfo& s : series_) {
            if (s.kind == kind && s.value == value && (source.empty() || s.source == source) &&
                std::find(joints.begin(), joints.end(), s.joint) == joints.end())
                joints.push_back(s.joint);
        }
        if (!joints.empty()) {
            std::sort(joints.begin(), joints.end());
            if (joints.front() == 0) {
                throw SpecError(
                    fmt::format("no {}: '{}' is not per joint (leave the joint out)", what, value));
            }
            throw SpecError(fmt::format("no {}: '{}' is per joint (joint = {} to {})", what, value,
                                        joints.front(), joints.back()));
        }
        std::vector<std::string> values;
        for (const SeriesInfo& s : series_) {
            if (s.kind == kind && std::find(values.begin(), values.end(), s.value) == values.end())
                values.push_back(s.value);
        }
        throw SpecError(fmt::format("no {}{}", what, suggest(value, values)));
    }
    std::string list;
    for (size_t i = 0; i < hits.size() && i < 5; ++i)
        list += (i > 0 ? ", '" : "'") + hits[i]->name + "'";
    throw SpecError(fmt::format("{} matches {} series ({}{}): give the source", what, hits.size(),
                                list, hits.size() > 5 ? ", ..." : ""));
}

std::vector<std::string> RunData::select(const std::vector<std::string>& patterns) const {
    std::vector<bool> chosen(series_.size(), false);
    const std::vector<std::string> all = names();
    for (const std::string& p : patterns) {
        SeriesKind kind;
        const bool is_kind = parse_series_kind(p, kind);
        const bool wild = p.find_first_of("*?") != std::string::npos;
        bool any = false;
        for (size_t i = 0; i < series_.size(); ++i) {
            const bool hit = is_kind
                                 ? series_[i].kind == kind
                                 : (wild ? glob_match(p, series_[i].name) : series_[i].name == p);
            if (hit) chosen[i] = any = true;
        }
        if (!any) {
            if (is_kind) throw SpecError(fmt::format("the run has no {} series", p));
            throw SpecError(fmt::format("{} '{}'{}", wild ? "no series matches" : "unknown series",
                                        p, suggest(p, all)));
        }
    }
    std::vector<std::string> out;
    for (size_t i = 0; i < series_.size(); ++i) {
        if (chosen[i]) out.push_back(series_[i].name);
    }
    return out;
}

SeriesData RunData::get(std::string_view name, double from, double to) const {
    return std::move(get(std::vector<std::string>{std::string(name)}, from, to)[0]);
}

std::vector<SeriesData> RunData::get(const std::vector<std::string>& names, double from,
                                     double to) const {
    if (std::isnan(from) || std::isnan(to)) {
        throw SpecError(fmt::format("the time range must be numbers (got {} to {})", from, to));
    }
    // columns to read, ascending, and where each requested name goes
    std::vector<size_t> columns{0};
    std::vector<SeriesData> out;
    std::vector<size_t> slot;  // per requested name: its index in `columns`
    for (const std::string& n : names) {
        const SeriesInfo& s = find(n);
        const size_t column = static_cast<size_t>(&s - series_.data()) + 1;
        SeriesData d;
        d.info = s;
        out.push_back(std::move(d));
        auto it = std::lower_bound(columns.begin(), columns.end(), column);
        if (it == columns.end() || *it != column) columns.insert(it, column);
    }
    for (const std::string& n : names) {
        const size_t column = index_.at(n) + 1;
        slot.push_back(static_cast<size_t>(
            std::lower_bound(columns.begin(), columns.end(), column) - columns.begin()));
    }
    std::vector<std::string> header{"time"};
    for (const SeriesInfo& s : series_)
        header.push_back(s.name);
    LineReader r((fs::path(dir_) / "data.csv").string());
    std::string_view line;
    std::string header_record;
    r.next_record(header_record);  // checked when the folder was opened
    std::vector<double> row(columns.size());
    while (r.next(line)) {
        parse_row(r, line, header.size(), columns, row.data(), header);
        const double t = row[0];
        if (!(t >= from && t <= to)) continue;
        for (size_t k = 0; k < out.size(); ++k) {
            out[k].time.push_back(t);
            out[k].values.push_back(row[slot[k]]);
        }
    }
    return out;
}

std::vector<double> RunData::times() const {
    LineReader r((fs::path(dir_) / "data.csv").string());
    std::string_view line;
    std::string header_record;
    r.next_record(header_record);
    std::vector<double> t;
    const std::vector<size_t> first{0};
    std::vector<std::string> header{"time"};
    for (const SeriesInfo& s : series_)
        header.push_back(s.name);
    double v = 0;
    while (r.next(line)) {
        parse_row(r, line, header.size(), first, &v, header);
        t.push_back(v);
    }
    return t;
}

long RunData::rows() const {
    LineReader r((fs::path(dir_) / "data.csv").string());
    std::string_view line;
    std::string header_record;
    if (!r.next_record(header_record)) return 0;
    long n = 0;
    while (r.next(line))
        ++n;
    return n;
}

bool RunData::truncated() const {
    LineReader r((fs::path(dir_) / "data.csv").string());
    std::string_view line;
    while (r.next(line)) {
    }
    return r.truncated();
}

std::vector<Event> RunData::events() const {
    std::vector<Event> out;
    const fs::path path = fs::path(dir_) / "events.csv";
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(path, ec))) return out;
    LineReader r(path.string());
    std::string record;
    std::vector<std::string> f;
    if (!r.next_record(record)) return out;  // empty, or a header cut short
    while (r.next_record(record)) {
        const std::string where = fmt::format("{}:{}", r.path(), r.record_line());
        if (!formats::split_line(record, f) || f.size() != 7) {
            throw FormatError(where +
                              ": 7 fields expected (tick,time,origin,kind,name,value,detail)");
        }
        Event e;
        char* end = nullptr;
        errno = 0;
        e.tick = std::strtol(f[0].c_str(), &end, 10);
        if (f[0].empty() || *end != '\0' || e.tick < 0 || errno == ERANGE) {
            throw FormatError(where + ": tick (a non-negative integer) expected, got '" + f[0] +
                              "'");
        }
        const auto origin = parse_origin(f[2]);
        if (!origin) {
            throw FormatError(where +
                              ": origin 'script', 'console', 'viewer' or 'file' "
                              "expected, got '" +
                              f[2] + "'");
        }
        e.origin = *origin;
        const auto kind = parse_event_kind(f[3]);
        if (!kind) {
            throw FormatError(where +
                              ": kind 'param', 'reload', 'reset', 'sensor' or 'drive' "
                              "expected, got '" +
                              f[3] + "'");
        }
        e.kind = *kind;
        e.name = f[4];
        if (!formats::parse_number(f[5], e.value)) {
            throw FormatError(where + ": value (a number) expected, got '" + f[5] + "'");
        }
        e.detail = f[6];
        out.push_back(std::move(e));
    }
    return out;
}

std::string RunData::log() const {
    const fs::path path = fs::path(dir_) / "log.txt";
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(path, ec))) return "";
    return read_own_file(path.string());
}

namespace {

// "time,<names>" and the rows of `d` as CSV
std::string csv_text(const std::vector<std::string>& names, const SeriesData* d, size_t count) {
    std::string text = "time";
    for (const std::string& n : names) {
        text += ',';
        formats::append_field(text, n);
    }
    text += '\n';
    const size_t rows = count == 0 ? 0 : d[0].time.size();
    for (size_t i = 0; i < rows; ++i) {
        formats::append_number(text, d[0].time[i]);
        for (size_t k = 0; k < count; ++k) {
            text += ',';
            formats::append_number(text, d[k].values[i]);
        }
        text += '\n';
    }
    return text;
}

}  // namespace

void RunData::refuse_own(const std::string& path) const {
    std::error_code ec;
    const fs::path target = fs::weakly_canonical(fs::absolute(path, ec), ec);
    const fs::path folder = fs::weakly_canonical(fs::absolute(dir_, ec), ec);
    if (target.empty() || folder.empty()) return;  // unresolvable: the write itself will say
    const fs::path relative = target.lexically_relative(folder);
    if (relative.empty() || *relative.begin() == "..") return;
    const std::string first = relative.begin()->string();
    const bool own =
        first == "config" || (std::next(relative.begin()) == relative.end() &&
                              (first == "run.json" || first == "series.csv" ||
                               first == "data.csv" || first == "events.csv" || first == "log.txt"));
    if (own) {
        throw IoError(fmt::format(
            "cannot write {}: it is {} of the run {} being read (write it elsewhere)", path,
            first == "config" ? "in the config/ folder" : "one of the files", dir_));
    }
}

void RunData::write_csv(const std::string& path, const std::vector<std::string>& names, double from,
                        double to) const {
    refuse_own(path);
    const std::vector<SeriesData> d = get(names, from, to);
    write_file_atomic(path, csv_text(names, d.data(), d.size()));
}

std::vector<std::string> RunData::write_split(const std::string& dir,
                                              const std::vector<std::string>& names, double from,
                                              double to) const {
    for (const std::string& n : names)
        find(n);  // unknown names fail before anything is written
    const std::vector<std::string> files = series_file_names(names);
    for (const std::string& f : files)
        refuse_own((fs::path(dir) / f).string());
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError(fmt::format("cannot create folder {}: {}", dir, ec.message()));
    std::vector<std::string> written;
    // a few hundred series per pass over data.csv: few passes, bounded memory
    constexpr size_t kBatch = 256;
    for (size_t first = 0; first < names.size(); first += kBatch) {
        const size_t end = std::min(names.size(), first + kBatch);
        const std::vector<std::string> batch(names.begin() + static_cast<long>(first),
                                             names.begin() + static_cast<long>(end));
        const std::vector<SeriesData> d = get(batch, from, to);
        for (size_t k = 0; k < batch.size(); ++k) {
            const std::string path = (fs::path(dir) / files[first + k]).string();
            write_file_atomic(path, csv_text({batch[k]}, &d[k], 1));
            written.push_back(path);
        }
    }
    return written;
}

Liveness liveness(const RunProcess& p) {
    if (p.pid <= 0) return Liveness::unknown;
    const RunProcess me = this_process();
    if (p.host != me.host) return Liveness::unknown;
    // a boot id that differs: the machine restarted since (every process of then is gone)
    if (!p.boot_id.empty() && !me.boot_id.empty() && p.boot_id != me.boot_id) {
        return Liveness::gone;
    }
    const std::uint64_t started = formats::process_start_time(p.pid);
    if (started == 0) {
        // /proc does not say (no such process, or /proc hides it): ask the kernel whether the
        // pid exists at all
        if (::kill(static_cast<pid_t>(p.pid), 0) != 0 && errno == ESRCH) return Liveness::gone;
        return Liveness::alive;
    }
    // the same pid, started at another time, is another process
    if (p.start_time != 0 && started != p.start_time) return Liveness::gone;
    return Liveness::alive;
}

namespace {

// the UTF-8 sequence at s[i], if well-formed: its length, else 0
size_t utf8_at(const std::string& s, size_t i) {
    const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c < 0x80) return 1;
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else {
        return 0;
    }
    if (i + n > s.size() || b(i + 1) < lo || b(i + 1) > hi) return 0;
    for (size_t k = 2; k < n; ++k) {
        if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
    }
    return n;
}

}  // namespace

std::vector<std::string> series_file_names(const std::vector<std::string>& names) {
    // 255 bytes is the longest file name of the usual file systems; room for ".csv" and "~N"
    constexpr size_t kMaxStem = 240;
    std::vector<std::string> out;
    std::set<std::string> taken;
    for (const std::string& name : names) {
        std::string stem;
        for (size_t i = 0; i < name.size();) {
            const auto c = static_cast<unsigned char>(name[i]);
            const size_t n = utf8_at(name, i);
            if (n == 0 || c < 0x20 || c == 0x7f || c == '/' || c == '\\') {
                stem += '_';
                i += n == 0 ? 1 : n;
                continue;
            }
            if (stem.size() + n > kMaxStem) break;  // whole characters only
            stem.append(name, i, n);
            i += n;
        }
        if (stem.empty() || stem[0] == '.' || stem[0] == '-') stem.insert(0, "_");
        std::string file = stem + ".csv";
        for (int k = 2; taken.count(file) > 0; ++k)
            file = fmt::format("{}~{}.csv", stem, k);
        taken.insert(file);
        out.push_back(file);
    }
    return out;
}

Comparison compare(const RunData& run, const RunData& replay) {
    Comparison c;
    c.series = run.series().size();
    const std::vector<std::string> a = run.names(), b = replay.names();
    if (a != b) {
        for (size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
            const std::string x = i < a.size() ? a[i] : "(none)";
            const std::string y = i < b.size() ? b[i] : "(none)";
            if (x != y) {
                c.difference = fmt::format(
                    "the series differ: column {} is '{}' in the run and "
                    "'{}' in the replay",
                    i + 2, x, y);
                return c;
            }
        }
    }
    LineReader ra((fs::path(run.dir()) / "data.csv").string());
    LineReader rb((fs::path(replay.dir()) / "data.csv").string());
    std::string_view la, lb;
    std::string header;
    ra.next_record(header);
    rb.next_record(header);
    std::vector<std::string> fa, fb;
    while (ra.next(la)) {
        if (!rb.next(lb)) {
            c.difference = fmt::format(
                "the replay ends after {} rows; the run goes on (line {} "
                "of its data.csv)",
                c.rows, ra.number());
            return c;
        }
        if (la != lb) {
            formats::split_line(la, fa);
            formats::split_line(lb, fb);
            for (size_t i = 0; i < std::min(fa.size(), fb.size()); ++i) {
                if (fa[i] != fb[i]) {
                    c.difference = fmt::format(
                        "first difference at t = {} s (data.csv line {}): {} is {} in the run "
                        "and {} in the replay",
                        fa[0], ra.number(), i == 0 ? "time" : a[i - 1], fa[i], fb[i]);
                    return c;
                }
            }
            c.difference = fmt::format("data.csv line {} differs in length", ra.number());
            return c;
        }
        ++c.rows;
    }
    // a run that ran to its end must not be shorter than its replay (one that was killed or
    // interrupted, or whose recording failed, stops earlier)
    const std::string& status = run.meta().status;
    if ((status == "finished" || (status == "failed" && !run.meta().recording_failed)) &&
        rb.next(lb)) {
        c.difference = fmt::format("the replay has more rows than the run ({})", c.rows);
        return c;
    }
    c.identical = true;
    return c;
}

}  // namespace gaitlab
