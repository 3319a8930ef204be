#include "gaitlab/plot.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <string_view>

#include <fmt/format.h>

#include "formats/csv.h"
#include "formats/run_files.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "gaitlab/run_data.h"

namespace gaitlab {

namespace fs = std::filesystem;

namespace {

// more curves than this make no readable plot, and would keep gnuplot busy for long
constexpr size_t kMaxPlotSeries = 1000;

}  // namespace

// a gnuplot string literal holding `s` as data, whatever its bytes: only letters, digits and a
// few punctuation marks appear as themselves; every other byte is an octal escape, so the
// script never holds a quote, backslash, backquote (command substitution), '@' (macros), '$',
// line end or any other character gnuplot could read as anything but part of the string
std::string gp_string(std::string_view s) {
    std::string out = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                           (c >= '0' && c <= '9') ||
                           std::string_view(" ._-+,:()[]/=*").find(ch) != std::string_view::npos;
        if (plain) {
            out += ch;
        } else {
            out += fmt::format("\\{:03o}", c);
        }
    }
    return out + "\"";
}

// runs `gnuplot SCRIPT` in `dir`, without a shell (fork and exec, the script's name as its only
// argument); returns "" or what went wrong
std::string run_gnuplot(const fs::path& dir, const std::string& script) {
    // "./" keeps a name starting with '-' from reading as an option
    const std::string arg = "./" + script;
    int err[2];
    if (pipe2(err, O_CLOEXEC) != 0)
        return fmt::format("cannot start gnuplot: {}", formats::reason(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        close(err[0]);
        close(err[1]);
        return fmt::format("cannot start gnuplot: {}", formats::reason(errno));
    }
    if (pid == 0) {
        // no gaitlab handler or ignored signal carries over to gnuplot
        for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE})
            signal(sig, SIG_DFL);
        dup2(err[1], STDERR_FILENO);
        const int null = open("/dev/null", O_RDWR);
        if (null >= 0) {
            dup2(null, STDIN_FILENO);
            dup2(null, STDOUT_FILENO);
        }
        close(err[0]);
        close(err[1]);
        if (chdir(dir.c_str()) != 0) _exit(126);
        execlp("gnuplot", "gnuplot", arg.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    close(err[1]);
    std::string messages;
    char buf[4096];
    for (;;) {
        const ssize_t n = read(err[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        if (messages.size() < 65536) messages.append(buf, static_cast<size_t>(n));
    }
    close(err[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
        return "cannot run gnuplot (install the gnuplot-nox package)";
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        // gnuplot's own message, on one line: it echoes the command that failed, marks the
        // place with '^', then says what is wrong ("gp" line 12: all points y value
        // undefined!), so the last line with words in it is the reason
        std::string line, reason;
        for (const char c : messages + "\n") {
            if (c == '\n') {
                if (line.find_first_not_of(" ^") != std::string::npos) reason = line;
                line.clear();
                continue;
            }
            // gnuplot may echo the script's text: no control characters reach the terminal
            line += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
        }
        const size_t start = reason.find_first_not_of(' ');
        if (start != std::string::npos) reason.erase(0, start);
        return fmt::format("gnuplot failed{}{}", reason.empty() ? "" : ": ", reason);
    }
    return "";
}

namespace {

// the one series `pattern` names, for the axis `axis` of a path plot
std::string one_series(const RunData& run, const std::string& pattern, const char* axis) {
    const std::vector<std::string> names = run.select({pattern});
    if (names.size() == 1) return names[0];
    std::string listed;
    for (size_t i = 0; i < names.size() && i < 5; ++i)
        listed += (i > 0 ? ", " : "") + names[i];
    throw SpecError(fmt::format("the {} axis takes one series; '{}' selects {} ({}{})", axis,
                                pattern, names.size(), listed, names.size() > 5 ? ", ..." : ""));
}

// The ranges and ticks of a path plot of one unit, for its data's [lo, hi] in x and y: each
// axis spans at least a quarter of the longer one, centred on its data, with a margin (a
// straight path is a line in a box, not a box of no height with its tick labels printed over
// each other), and both share one tick step, about six over the longer axis (1, 2 or 5 times a
// power of ten), where gnuplot's own would crowd the shorter axis. Spans too large for a double
// keep gnuplot's own ranges and ticks.
std::string one_scale_ranges(const double lo[2], const double hi[2]) {
    const double longer = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-9});
    std::string gp;
    for (int k = 0; k < 2; ++k) {
        const double mid = 0.5 * lo[k] + 0.5 * hi[k];
        const double half = 0.55 * std::max(hi[k] - lo[k], 0.25 * longer);
        if (!std::isfinite(mid - half) || !std::isfinite(mid + half)) return {};
        gp += fmt::format("set {}range [{:.17g}:{:.17g}]\n", k == 0 ? 'x' : 'y', mid - half,
                          mid + half);
    }
    const double raw = 1.1 * longer / 6;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw <= power       ? power
                        : raw <= 2 * power ? 2 * power
                        : raw <= 5 * power ? 5 * power
                                           : 10 * power;
    if (std::isfinite(step) && step > 0) {
        gp += fmt::format("set xtics {0:.17g}\nset ytics {0:.17g}\n", step);
    }
    return gp;
}

// "t1 s to t2 s" as messages state a time range
std::string describe_range(double from, double to) {
    if (std::isinf(from) && std::isinf(to)) return "in the whole run";
    if (std::isinf(to)) return fmt::format("from {} s on", from);
    if (std::isinf(from)) return fmt::format("up to {} s", to);
    return fmt::format("between {} s and {} s", from, to);
}

// "name (unit)", or the name alone
std::string with_unit(const RunData& run, const std::string& name) {
    const std::string& u = run.find(name).unit;
    return u.empty() ? name : name + " (" + u + ")";
}

}  // namespace

PlotFiles plot(const RunData& run, const PlotOptions& o) {
    const fs::path png(o.output);
    if (png.extension() != ".png" || png.stem().empty()) {
        throw SpecError(fmt::format("plot output must be a .png file (got '{}')", o.output));
    }
    const bool path_plot = !o.x.empty() || !o.y.empty();
    if (path_plot && (o.x.empty() || o.y.empty())) {
        throw SpecError("a path plot needs two series: x and y");
    }
    if (path_plot && !o.series.empty()) {
        throw SpecError(
            "a plot shows series against time or one series against another (x and y), not "
            "both");
    }
    if (!path_plot && o.series.empty()) {
        throw SpecError("nothing to plot: give at least one series");
    }
    if (o.width < 100 || o.width > 10000 || o.height < 100 || o.height > 10000) {
        throw SpecError(fmt::format("plot size must be 100 to 10000 pixels each way (got {}x{})",
                                    o.width, o.height));
    }
    std::vector<std::string> names;
    long rows = 0;  // rows of a path plot
    // a path plot's ranges, [lo, hi] for x and for y, over the rows that hold two numbers
    double lo[2] = {0, 0}, hi[2] = {0, 0};
    if (path_plot) {
        names = {one_series(run, o.x, "x"), one_series(run, o.y, "y")};
        if (names[0] == names[1]) {
            throw SpecError(fmt::format("x and y are the same series ('{}'): give two", names[0]));
        }
        const std::vector<SeriesData> d = run.get(names, o.from, o.to);
        if (d[0].time.empty()) {
            throw SpecError(fmt::format("nothing to plot: the run has no rows {}",
                                        describe_range(o.from, o.to)));
        }
        for (int k = 0; k < 2; ++k) {
            const auto& v = d[static_cast<size_t>(k)].values;
            if (std::none_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); })) {
                throw SpecError(fmt::format(
                    "nothing to plot: '{}' holds no numbers {} (only NaN or infinite values)",
                    names[static_cast<size_t>(k)], describe_range(o.from, o.to)));
            }
        }
        rows = static_cast<long>(d[0].time.size());
        long points = 0;  // rows that hold two numbers
        for (size_t i = 0; i < d[0].time.size(); ++i) {
            const double v[2] = {d[0].values[i], d[1].values[i]};
            if (!std::isfinite(v[0]) || !std::isfinite(v[1])) continue;
            for (int k = 0; k < 2; ++k) {
                lo[k] = points == 0 ? v[k] : std::min(lo[k], v[k]);
                hi[k] = points == 0 ? v[k] : std::max(hi[k], v[k]);
            }
            ++points;
        }
        if (points == 0) {
            throw SpecError(
                fmt::format("nothing to plot: '{}' and '{}' are never numbers at once {}", names[0],
                            names[1], describe_range(o.from, o.to)));
        }
    } else {
        names = run.select(o.series);
    }
    if (names.size() > kMaxPlotSeries) {
        throw SpecError(fmt::format("a plot shows at most {} series (got {}): select fewer",
                                    kMaxPlotSeries, names.size()));
    }
    PlotFiles files;
    files.png = o.output;
    files.script = (png.parent_path() / (png.stem().string() + ".gp")).string();
    files.data = (png.parent_path() / (png.stem().string() + ".csv")).string();
    for (const std::string& f : {files.png, files.script, files.data})
        run.refuse_own(f);
    std::error_code ec;
    if (!png.parent_path().empty()) fs::create_directories(png.parent_path(), ec);
    run.write_csv(files.data, names, o.from, o.to);
    // the header is one line unless a name holds a line end (quoted, as CSV does)
    std::string header = "time";
    for (const std::string& n : names) {
        header += ',';
        formats::append_field(header, n);
    }
    const auto header_lines = 1 + std::count(header.begin(), header.end(), '\n');

    // every text that comes from the user or the run folder (file names, title, series names,
    // units) goes through gp_string; comments hold none of it
    std::string gp =
        "# gaitlab plot: edit this file, then run gnuplot on it in this folder to redraw the PNG\n";
    gp += path_plot ? "# from the CSV file next to it (time in column 1, x in column 2, y in "
                      "column 3)\n"
                    : "# from the CSV file next to it (time in column 1, then one column per "
                      "series)\n";
    gp += fmt::format("set terminal pngcairo size {},{} noenhanced font \"sans,10\"\n", o.width,
                      o.height);
    gp += "set output " + gp_string(png.filename().string()) + "\n";
    gp += "set datafile separator \",\"\n";
    gp += "set key outside right top noenhanced\nset grid\n";
    gp += "set title " + gp_string(o.title.empty() ? run.meta().name : o.title) + "\n";
    const std::string data_name = gp_string(png.stem().string() + ".csv");
    if (path_plot) {
        gp += "set xlabel " + gp_string(with_unit(run, names[0])) + "\n";
        gp += "set ylabel " + gp_string(with_unit(run, names[1])) + "\n";
        // a path keeps its shape: one metre is as long across as up (for series of one unit)
        if (run.find(names[0]).unit == run.find(names[1]).unit) {
            gp += "set size ratio -1\n";
            gp += one_scale_ranges(lo, hi);
        }
        // the line, then where it starts and ends (the first and last rows)
        const long last = rows - 1;
        gp += fmt::format(
            "plot {} using 2:3 skip {} with lines title {}, \\\n"
            "     \"\" using 2:3 skip {} every ::0::0 with points pt 7 title \"start\", \\\n"
            "     \"\" using 2:3 skip {} every ::{}::{} with points pt 5 title \"end\"\n",
            data_name, header_lines, gp_string(names[1] + " against " + names[0]), header_lines,
            header_lines, last, last);
    } else {
        std::vector<std::string> units;
        for (const std::string& n : names) {
            const std::string& u = run.find(n).unit;
            if (!u.empty() && std::find(units.begin(), units.end(), u) == units.end())
                units.push_back(u);
        }
        gp += "set xlabel \"time (s)\"\n";
        std::string ylabel;
        for (size_t i = 0; i < units.size(); ++i)
            ylabel += (i > 0 ? ", " : "") + units[i];
        gp += "set ylabel " + gp_string(ylabel) + "\n";
        for (size_t i = 0; i < names.size(); ++i) {
            gp += i == 0 ? "plot " : ", \\\n     ";
            gp += fmt::format("{} using 1:{} skip {} with lines title {}",
                              i == 0 ? data_name : "\"\"", i + 2, header_lines,
                              gp_string(with_unit(run, names[i])));
        }
        gp += "\n";
    }
    write_file_atomic(files.script, gp);

    const fs::path dir = png.parent_path().empty() ? fs::path(".") : png.parent_path();
    const std::string error = run_gnuplot(dir, png.stem().string() + ".gp");
    if (!error.empty()) {
        throw IoError(fmt::format("{} (the script and data are in {} and {})", error, files.script,
                                  files.data));
    }
    return files;
}

PlotFiles plot_table(const TablePlot& t) {
    const fs::path png(t.output);
    if (png.extension() != ".png" || png.stem().empty()) {
        throw SpecError(fmt::format("plot output must be a .png file (got '{}')", t.output));
    }
    if (t.columns.size() < 2) {
        throw SpecError(
            fmt::format("a table plot needs an x column and at least one curve (got "
                        "{} columns)",
                        t.columns.size()));
    }
    if (t.width < 100 || t.height < 100 || t.width > 10000 || t.height > 10000) {
        throw SpecError(fmt::format("plot size must be 100 to 10000 pixels each way (got {}x{})",
                                    t.width, t.height));
    }
    PlotFiles files;
    files.png = t.output;
    files.script = (png.parent_path() / (png.stem().string() + ".gp")).string();
    files.data = (png.parent_path() / (png.stem().string() + ".csv")).string();
    // one header line: names with a line end would make two
    std::string csv;
    for (size_t i = 0; i < t.columns.size(); ++i) {
        if (t.columns[i].find_first_of("\r\n") != std::string::npos) {
            throw SpecError(
                fmt::format("table plot column {}: a name without line ends expected", i + 1));
        }
        if (i > 0) csv += ',';
        formats::append_field(csv, t.columns[i]);
    }
    csv += '\n';
    for (size_t r = 0; r < t.rows.size(); ++r) {
        if (t.rows[r].size() != t.columns.size()) {
            throw SpecError(
                fmt::format("table plot row {}: {} values expected (one per column), "
                            "got {}",
                            r + 1, t.columns.size(), t.rows[r].size()));
        }
        for (size_t i = 0; i < t.rows[r].size(); ++i) {
            const double v = t.rows[r][i];
            csv += i > 0 ? "," : "";
            // gnuplot leaves a NaN out of the curve
            csv += std::isfinite(v) ? fmt::format("{}", v) : std::string("NaN");
        }
        csv += '\n';
    }
    write_file_atomic(files.data, csv, MissingFolders::create);

    // every text that comes from the caller goes through gp_string
    std::string gp =
        "# gaitlab plot: edit this file, then run gnuplot on it in this folder to redraw the PNG\n"
        "# from the CSV file next to it (x in column 1, then one column per curve)\n";
    gp += fmt::format("set terminal pngcairo size {},{} noenhanced font \"sans,10\"\n", t.width,
                      t.height);
    gp += "set output " + gp_string(png.filename().string()) + "\n";
    gp += "set datafile separator \",\"\n";
    gp += "set key outside right top noenhanced\nset grid\n";
    gp += "set title " + gp_string(t.title) + "\n";
    gp += "set xlabel " + gp_string(t.xlabel) + "\n";
    gp += "set ylabel " + gp_string(t.ylabel) + "\n";
    const std::string data_name = gp_string(png.stem().string() + ".csv");
    for (size_t i = 1; i < t.columns.size(); ++i) {
        gp += i == 1 ? "plot " : ", \\\n     ";
        gp += fmt::format("{} using 1:{} skip 1 with linespoints title {}",
                          i == 1 ? data_name : "\"\"", i + 1, gp_string(t.columns[i]));
    }
    gp += "\n";
    write_file_atomic(files.script, gp);

    const fs::path dir = png.parent_path().empty() ? fs::path(".") : png.parent_path();
    const std::string error = run_gnuplot(dir, png.stem().string() + ".gp");
    if (!error.empty()) {
        throw IoError(fmt::format("{} (the script and data are in {} and {})", error, files.script,
                                  files.data));
    }
    return files;
}

}  // namespace gaitlab
