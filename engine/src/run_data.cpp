#include "gaitlab/run_data.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

#include "data/csv.h"
#include "data/files.h"
#include "data/json.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "gaitlab/suggest.h"

namespace gaitlab {

namespace fs = std::filesystem;
using data::Json;

namespace {

// complete lines of a file, one at a time; a last line without its line end is dropped and
// remembered as truncated
class LineReader {
  public:
    explicit LineReader(const std::string& path) : path_(path) {
        file_ = std::fopen(path.c_str(), "rb");
        if (!file_) {
            throw IoError(fmt::format("cannot read {}: {}", path, data::reason(errno)));
        }
    }
    ~LineReader() {
        std::free(buf_);
        if (file_) std::fclose(file_);
    }
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    bool next(std::string_view& line) {
        const ssize_t n = ::getline(&buf_, &cap_, file_);
        if (n <= 0) return false;
        if (buf_[n - 1] != '\n') {
            truncated_ = true;
            return false;
        }
        ++number_;
        size_t len = static_cast<size_t>(n - 1);
        if (len > 0 && buf_[len - 1] == '\r') --len;
        line = std::string_view(buf_, len);
        return true;
    }
    long number() const { return number_; }
    bool truncated() const { return truncated_; }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
    std::FILE* file_ = nullptr;
    char* buf_ = nullptr;
    size_t cap_ = 0;
    long number_ = 0;
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
            if (!data::parse_number(text, out[w])) {
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
            fmt::format("{}: kind 'robot', 'controller' or 'sensor' expected, got "
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

RunMeta meta_from(const Json& j, const std::string& file) {
    if (j.type() != Json::Type::object || j.str_at("format") != "gaitlab run") {
        throw FormatError(fmt::format(
            "{}:1: not a gaitlab run description (an object with \"format\": \"gaitlab run\" "
            "expected)",
            file));
    }
    RunMeta m;
    m.name = j.str_at("name");
    m.status = j.str_at("status");
    m.message = j.str_at("message");
    m.started = j.str_at("started");
    m.ended = j.str_at("ended");
    m.first_tick = static_cast<long>(j.int_at("first_tick", 0));
    m.last_tick = static_cast<long>(j.int_at("last_tick", -1));
    if (const Json* s = j.find("simulation")) {
        m.simulation = static_cast<int>(s->int_at("index", 1));
        m.options.dt = s->num_at("dt", m.options.dt);
        m.options.control_every = static_cast<int>(s->int_at("control_every", 30));
        m.options.solver_iterations = static_cast<int>(s->int_at("solver_iterations", 20));
        if (const Json* seed = s->find("seed")) m.options.seed = seed->uint(0);
        if (s->str_at("on_controller_error") == "continue") {
            m.options.on_controller_error = ControllerErrorPolicy::continue_;
        }
    }
    if (const Json* r = j.find("recording")) {
        m.record_every = static_cast<int>(r->int_at("record_every", 0));
        m.flush_seconds = r->num_at("flush_seconds", 2);
        if (const Json* sel = r->find("select")) {
            for (const Json& p : sel->items())
                m.select.push_back(p.str());
        }
    }
    if (const Json* r = j.find("run")) {
        m.script = r->str_at("script");
        if (const Json* args = r->find("args")) {
            for (const Json& a : args->items())
                m.args.push_back(a.str());
        }
        if (const Json* seed = r->find("seed")) m.script_seed = seed->uint(0);
        if (const Json* by = r->find("started_by")) m.started_by = by->str("simulation");
    }
    if (const Json* files = j.find("config")) {
        for (const Json& f : files->items()) {
            ConfigFile c;
            c.role = f.str_at("role");
            c.path = f.str_at("path");
            c.origin = f.str_at("origin");
            c.of = f.str_at("of");
            if (const Json* v = f.find("version")) c.version = v->uint(0);
            m.files.push_back(std::move(c));
        }
    }
    if (const Json* p = j.find("provenance")) {
        for (const auto& [k, v] : p->members())
            m.provenance.emplace_back(k, v.str());
    }
    return m;
}

}  // namespace

RunData::RunData(std::string dir) : dir_(std::move(dir)) {
    std::error_code ec;
    const fs::path p(dir_);
    if (!fs::exists(p, ec)) throw IoError(fmt::format("no run folder at {}", dir_));
    if (!fs::is_directory(p, ec)) {
        throw IoError(fmt::format("{} is not a run folder: it is not a folder", dir_));
    }
    std::vector<std::string> missing;
    for (const char* f : {"run.json", "series.csv", "data.csv"}) {
        if (!fs::exists(p / f, ec)) missing.emplace_back(f);
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
    const std::string meta_path = (p / "run.json").string();
    meta_ = meta_from(Json::parse(read_file(meta_path), meta_path), meta_path);

    LineReader list((p / "series.csv").string());
    std::string_view line;
    std::vector<std::string> f;
    if (!list.next(line) || !data::split_line(line, f) || f.size() != 7 || f[0] != "name") {
        throw FormatError(fmt::format(
            "{}:1: header 'name,kind,source,value,joint,body,unit' expected", list.path()));
    }
    while (list.next(line)) {
        if (!data::split_line(line, f) || f.size() != 7) {
            throw FormatError(
                fmt::format("{}:{}: 7 fields expected (name,kind,source,value,"
                            "joint,body,unit)",
                            list.path(), list.number()));
        }
        series_.push_back(series_from(f, fmt::format("{}:{}", list.path(), list.number())));
    }

    LineReader rows((p / "data.csv").string());
    if (!rows.next(line) || !data::split_line(line, f) || f.empty() || f[0] != "time") {
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

std::vector<std::string> RunData::names() const {
    std::vector<std::string> n;
    for (const SeriesInfo& s : series_)
        n.push_back(s.name);
    return n;
}

const SeriesInfo& RunData::find(std::string_view name) const {
    for (const SeriesInfo& s : series_) {
        if (s.name == name) return s;
    }
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
        const size_t column = static_cast<size_t>(&find(n) - series_.data()) + 1;
        slot.push_back(static_cast<size_t>(
            std::lower_bound(columns.begin(), columns.end(), column) - columns.begin()));
    }
    std::vector<std::string> header{"time"};
    for (const SeriesInfo& s : series_)
        header.push_back(s.name);
    LineReader r((fs::path(dir_) / "data.csv").string());
    std::string_view line;
    r.next(line);  // the header, checked when the folder was opened
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
    r.next(line);
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
    long n = -1;  // the header
    while (r.next(line))
        ++n;
    return n < 0 ? 0 : n;
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
    if (!fs::exists(path, ec)) return out;
    LineReader r(path.string());
    std::string_view line;
    std::vector<std::string> f;
    if (!r.next(line)) return out;  // empty, or a header cut short
    while (r.next(line)) {
        const std::string where = fmt::format("{}:{}", r.path(), r.number());
        if (!data::split_line(line, f) || f.size() != 7) {
            throw FormatError(where +
                              ": 7 fields expected (tick,time,origin,kind,name,value,detail)");
        }
        Event e;
        char* end = nullptr;
        e.tick = std::strtol(f[0].c_str(), &end, 10);
        if (f[0].empty() || *end != '\0' || e.tick < 0) {
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
        if (!data::parse_number(f[5], e.value)) {
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
    if (!fs::exists(path, ec)) return "";
    return read_file(path.string());
}

void RunData::write_csv(const std::string& path, const std::vector<std::string>& names, double from,
                        double to) const {
    const std::vector<SeriesData> d = get(names, from, to);
    std::string text = "time";
    for (const std::string& n : names) {
        text += ',';
        data::append_field(text, n);
    }
    text += '\n';
    const size_t n = d.empty() ? 0 : d[0].time.size();
    for (size_t i = 0; i < n; ++i) {
        data::append_number(text, d[0].time[i]);
        for (const SeriesData& s : d) {
            text += ',';
            data::append_number(text, s.values[i]);
        }
        text += '\n';
    }
    write_file_atomic(path, text);
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
    ra.next(la);
    rb.next(lb);
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
            data::split_line(la, fa);
            data::split_line(lb, fb);
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
    // a run that finished must not be shorter than its replay
    if (run.meta().status != "running" && rb.next(lb)) {
        c.difference = fmt::format("the replay has more rows than the run ({})", c.rows);
        return c;
    }
    c.identical = true;
    return c;
}

}  // namespace gaitlab
