// Parameter sweeps (see gaitlab/optimize/sweep.h).
#include "gaitlab/optimize/sweep.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/suggest.h"
#include "results.h"

namespace gaitlab::optimize {

namespace {

namespace fs = std::filesystem;

const char* const kSyntax = "NAME=FROM:TO:STEP expected, e.g. phase=30:180:15";

// a finite number, the whole text
bool parse_number(const std::string& text, double& v) {
    if (text.empty()) return false;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    return r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

// the digits after the decimal point of a number written plainly ("0.25": 2, "30": 0); -1 for
// another form ("1e-3") or more than 15 of them
int decimals(const std::string& text) {
    if (text.find_first_not_of("+-0123456789.") != std::string::npos) return -1;
    const auto dot = text.find('.');
    const int n = dot == std::string::npos ? 0 : static_cast<int>(text.size() - dot - 1);
    return n <= 15 ? n : -1;
}

std::string names_of(const Spec& spec) {
    std::string out;
    for (const Parameter& p : spec.parameters)
        out += (out.empty() ? "" : ", ") + p.name;
    return out;
}

// a value as the table and the messages write it: the shortest text that reads back exactly
std::string text_of(double v) {
    return fmt::format("{}", v);
}

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

// the table: one row per point, in grid order
std::string table_text(const Spec& spec, const Grid& grid,
                       const std::vector<std::vector<double>>& xs,
                       const std::vector<Evaluation>& ev) {
    std::string out;
    for (const Axis& a : grid.axes)
        out += csv_field(spec.parameters[a.parameter].name) + ",";
    out += "fitness,error\n";
    for (std::size_t i = 0; i < ev.size(); ++i) {
        for (const Axis& a : grid.axes)
            out += text_of(xs[i][a.parameter]) + ",";
        // NaN for a failed point: gnuplot leaves its cell of the heat map blank
        out += ev[i].failed() ? "NaN" : text_of(ev[i].fitness);
        out += "," + csv_field(ev[i].error) + "\n";
    }
    return out;
}

// the gnuplot script that draws OUT/sweep.png from OUT/sweep.csv
std::string plot_script(const Spec& spec, const Grid& grid, const std::vector<double>& best,
                        double best_fitness) {
    std::string at;
    for (const Axis& a : grid.axes)
        at += fmt::format("{}{} {}", at.empty() ? "" : ", ", spec.parameters[a.parameter].name,
                          text_of(best[a.parameter]));
    const std::string title =
        fmt::format("{}: {} over the grid (best {:.6g} at {})",
                    fs::path(spec.file).filename().string(), spec.fitness, best_fitness, at);
    std::string gp =
        "# gaitlab sweep: edit this file, then run gnuplot on it in this folder to redraw "
        "sweep.png\n# from sweep.csv (one column per swept parameter, then fitness; NaN: "
        "failed)\n";
    gp += "set terminal pngcairo size 1000,700 noenhanced font \"sans,10\"\n";
    gp += "set output \"sweep.png\"\n";
    gp += "set datafile separator \",\"\n";
    gp += "set title " + gp_string(title) + "\n";
    // the table's header is one line unless a name holds a line end (quoted, as CSV does)
    std::size_t header_lines = 1;
    for (const Axis& a : grid.axes) {
        const std::string& name = spec.parameters[a.parameter].name;
        header_lines += static_cast<std::size_t>(std::count(name.begin(), name.end(), '\n'));
    }
    const std::string skip = std::to_string(header_lines);
    const Axis& x = grid.axes[0];
    const std::string& xname = spec.parameters[x.parameter].name;
    gp += "set xlabel " + gp_string(xname) + "\n";
    const double bx = best[x.parameter];
    if (grid.axes.size() == 1) {
        gp += "set ylabel " + gp_string(spec.fitness) + "\nset grid\nset key top left\n";
        gp += fmt::format(
            "set label 1 \"\" at {:.17g},{:.17g} point pt 6 ps 2 lw 2 lc rgb \"#d62728\"\n", bx,
            best_fitness);
        gp += "plot \"sweep.csv\" using 1:2 skip " + skip + " with linespoints pt 7 ps 0.6 title " +
              gp_string(spec.fitness) + "\n";
        return gp;
    }
    const Axis& y = grid.axes[1];
    const double by = best[y.parameter];
    // the cells of the heat map: each value at the middle of its cell
    const auto half = [](const Axis& a) { return (a.values[1] - a.values[0]) / 2; };
    gp += "set ylabel " + gp_string(spec.parameters[y.parameter].name) + "\n";
    gp += "set cblabel " + gp_string(spec.fitness) + "\n";
    gp += fmt::format("set xrange [{:.17g}:{:.17g}]\nset yrange [{:.17g}:{:.17g}]\n",
                      x.values.front() - half(x), x.values.back() + half(x),
                      y.values.front() - half(y), y.values.back() + half(y));
    gp +=
        "set palette defined (0 \"#440154\", 0.25 \"#3b528b\", 0.5 \"#21918c\", "
        "0.75 \"#5ec962\", 1 \"#fde725\")\n";
    gp += fmt::format(
        "set label 1 \"\" at {:.17g},{:.17g} point pt 6 ps 2 lw 2 lc rgb \"#d62728\" front\n", bx,
        by);
    gp += "plot \"sweep.csv\" using 1:2:3 skip " + skip + " with image notitle\n";
    return gp;
}

}  // namespace

std::size_t Grid::points() const {
    std::size_t n = 1;
    for (const Axis& a : axes)
        n *= a.values.size();
    return n;
}

std::vector<double> Grid::point(std::size_t i) const {
    std::vector<double> x = base;
    for (auto a = axes.rbegin(); a != axes.rend(); ++a) {
        x[a->parameter] = a->values[i % a->values.size()];
        i /= a->values.size();
    }
    return x;
}

Grid parse_grid(const Spec& spec, const std::vector<std::string>& args) {
    Grid grid;
    // off the grid: the spec's initial point, or the centre of each range (integers rounded)
    for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
        const Parameter& p = spec.parameters[i];
        double v = spec.initial.empty() ? (p.min + p.max) / 2 : spec.initial[i];
        if (p.integer) v = std::clamp(std::round(v), std::ceil(p.min), std::floor(p.max));
        grid.base.push_back(v);
    }
    if (args.empty()) {
        throw SpecError(fmt::format("--grid: at least one {} ({})", kSyntax, names_of(spec)));
    }
    double total = 1;
    for (const std::string& arg : args) {
        const auto bad = [&](const std::string& what) {
            throw SpecError(fmt::format("--grid '{}': {}", arg, what));
        };
        const auto eq = arg.find('=');
        if (eq == std::string::npos || eq == 0) bad(kSyntax);
        const std::string name = arg.substr(0, eq);
        std::vector<std::string> parts;
        for (std::size_t from = eq + 1;;) {
            const auto colon = arg.find(':', from);
            parts.push_back(arg.substr(from, colon == std::string::npos ? colon : colon - from));
            if (colon == std::string::npos) break;
            from = colon + 1;
        }
        if (parts.size() != 3) bad(kSyntax);
        double from = 0, to = 0, step = 0;
        const char* what[] = {"FROM", "TO", "STEP"};
        double* value[] = {&from, &to, &step};
        for (int k = 0; k < 3; ++k) {
            if (!parse_number(parts[static_cast<std::size_t>(k)], *value[k])) {
                bad(fmt::format("{}: a number expected, got '{}' ({})", what[k],
                                parts[static_cast<std::size_t>(k)], kSyntax));
            }
        }
        std::vector<std::string> names;
        for (const Parameter& p : spec.parameters)
            names.push_back(p.name);
        const auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) {
            bad(fmt::format("unknown parameter '{}'{} (the spec's parameters: {})", name,
                            did_you_mean(name, names), names_of(spec)));
        }
        Axis axis;
        axis.parameter = static_cast<std::size_t>(it - names.begin());
        const Parameter& p = spec.parameters[axis.parameter];
        for (const Axis& a : grid.axes) {
            if (a.parameter == axis.parameter) bad(fmt::format("'{}' is swept twice", name));
        }
        if (!(step > 0)) bad(fmt::format("STEP {}: a step > 0 expected", text_of(step)));
        if (from == to) {
            bad(fmt::format("the range {}:{} is empty (FROM < TO expected)", text_of(from),
                            text_of(to)));
        }
        if (from > to) {
            bad(fmt::format("the range {}:{} is inverted (FROM < TO expected)", text_of(from),
                            text_of(to)));
        }
        if (p.integer && (from != std::floor(from) || step != std::floor(step))) {
            bad(
                fmt::format("'{}' is an integer parameter: whole numbers expected for FROM and "
                            "STEP",
                            name));
        }
        // the values FROM + k STEP up to TO (a last value within rounding of TO is TO)
        const double q = (to - from) / step;
        if (q + 1 > static_cast<double>(kMaxGridPoints)) {
            bad(fmt::format("{} values on one axis; a grid has at most {} points", q + 1,
                            kMaxGridPoints));
        }
        const auto n = static_cast<std::size_t>(std::floor(q + 1e-9)) + 1;
        if (n < 2) {
            bad(
                fmt::format("STEP {} is larger than the range {}:{}: one value (a smaller step "
                            "expected)",
                            text_of(step), text_of(from), text_of(to)));
        }
        // FROM and STEP written as decimals (30, 0.25): the values computed in whole units of
        // their last decimal, so that 0:1:0.1 gives 0.3, not 0.30000000000000004
        const int places = std::max(decimals(parts[0]), decimals(parts[2]));
        const double scale = places >= 0 ? std::pow(10.0, places) : 0;
        const bool exact = places >= 0 && std::fabs(std::round(from * scale)) < 0x1p52 &&
                           std::fabs(std::round(to * scale)) < 0x1p52;
        for (std::size_t k = 0; k < n; ++k) {
            double v = exact ? (std::round(from * scale) +
                                static_cast<double>(k) * std::round(step * scale)) /
                                   scale
                             : from + static_cast<double>(k) * step;
            if (k + 1 == n && std::fabs(v - to) <= 1e-9 * step) v = to;
            axis.values.push_back(std::min(v, to));
        }
        for (const double v : {axis.values.front(), axis.values.back()}) {
            if (v < p.min || v > p.max) {
                bad(fmt::format("{} is outside {}'s range [{}, {}] in {}", text_of(v), name,
                                text_of(p.min), text_of(p.max), spec.file));
            }
        }
        total *= static_cast<double>(n);
        if (total > static_cast<double>(kMaxGridPoints)) {
            std::string sizes;
            for (const Axis& a : grid.axes)
                sizes += fmt::format("{} x ", a.values.size());
            throw SpecError(fmt::format("--grid: {}{} = {} points; a grid has at most {}", sizes, n,
                                        total, kMaxGridPoints));
        }
        grid.axes.push_back(std::move(axis));
    }
    return grid;
}

SweepResult run_sweep(const Spec& spec, const Grid& grid, const SweepOptions& options,
                      const std::atomic<int>* stop,
                      const std::function<void(const SweepTick&)>& on_evaluation) {
    if (options.workers < 1) {
        throw SpecError(
            fmt::format("--workers: a whole number >= 1 expected, got {}", options.workers));
    }
    SweepResult result;
    result.points = grid.points();
    result.best_fitness = std::numeric_limits<double>::quiet_NaN();
    const fs::path out(options.out);
    detail::open_results_folder(options.out);
    const fs::path jsonl_path = out / "evaluations.jsonl";
    std::ofstream jsonl(jsonl_path, std::ios::binary | std::ios::trunc);
    if (!jsonl) {
        throw IoError(
            fmt::format("{}: cannot create{}", jsonl_path.string(), detail::reason(errno)));
    }

    EvaluationPool pool(spec, options.workers, options.seed, stop, options.backend);
    const auto started = std::chrono::steady_clock::now();
    SweepTick tick;
    tick.points = result.points;
    tick.best = result.best_fitness;
    const EvaluationDone ticked = [&](std::size_t, const Evaluation& e) {
        if (!on_evaluation) return;
        const double fitness = e.failed() ? std::numeric_limits<double>::quiet_NaN() : e.fitness;
        ++tick.done;
        if (std::isfinite(fitness) && !(fitness <= tick.best)) tick.best = fitness;
        tick.wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        on_evaluation(tick);
    };
    // in chunks, each written to evaluations.jsonl when it ends (an interrupted sweep keeps the
    // chunks done); the chunks' size changes nothing in the results
    const std::size_t chunk = 16 * static_cast<std::size_t>(pool.workers());
    std::vector<std::vector<double>> all;
    std::vector<Evaluation> evaluations;
    for (std::size_t first = 0; first < result.points; first += chunk) {
        std::vector<std::vector<double>> xs;
        for (std::size_t i = first; i < std::min(result.points, first + chunk); ++i)
            xs.push_back(grid.point(i));
        const std::vector<Evaluation> ev = pool.evaluate(xs, ticked);
        if (stop && stop->load() != 0) {
            throw Error(fmt::format("interrupted after {} of {} points", first, result.points));
        }
        std::string lines;
        for (std::size_t k = 0; k < ev.size(); ++k) {
            const std::size_t i = first + k;
            lines += detail::evaluation_line(spec, 0, i, xs[k], ev[k]);
            if (ev[k].failed()) {
                if (result.failed++ == 0) result.first_error = ev[k].error;
            } else if (result.best.empty() || ev[k].fitness > result.best_fitness) {
                result.best = xs[k];
                result.best_fitness = ev[k].fitness;
                result.best_point = i;
            }
        }
        detail::append_text(jsonl, jsonl_path, lines);
        all.insert(all.end(), xs.begin(), xs.end());
        evaluations.insert(evaluations.end(), ev.begin(), ev.end());
    }

    result.table = (out / "sweep.csv").string();
    detail::write_file(result.table, table_text(spec, grid, all, evaluations));

    if (grid.axes.size() > 2) {
        result.plot_error = fmt::format(
            "no plot for {} swept parameters (one: a line plot, two: "
            "a heat map)",
            grid.axes.size());
    } else if (result.best.empty()) {
        result.plot_error = "no plot: every point failed";
    } else {
        detail::write_file((out / "sweep.gp").string(),
                           plot_script(spec, grid, result.best, result.best_fitness));
        result.plot_error = run_gnuplot(out, "sweep.gp");
        if (result.plot_error.empty()) result.plot = (out / "sweep.png").string();
    }

    if (!result.best.empty()) {
        const fs::path path = fs::absolute(out / "best" / "best.xml");
        try {
            Evaluator(spec, options.seed).save(result.best, path.string());
            result.simulation = (out / "best" / "best.xml").string();
        } catch (const Error& e) {
            result.simulation_error = e.what();
        }
    }

    nlohmann::ordered_json best;
    best["format"] = "gaitlab-optimize-best";
    best["version"] = 1;
    best["spec"] = spec.file;
    best["method"] = "sweep";
    best["seed"] = options.seed;
    best["generations"] = 1;
    best["population"] = result.points;
    best["evaluations"] = result.points;
    best["fitness_kind"] = spec.fitness;
    best["fitness"] = detail::fitness_json(result.best_fitness);
    best["parameters"] = result.best.empty() ? nlohmann::ordered_json(nullptr)
                                             : detail::parameters_json(spec, result.best);
    if (!result.best.empty()) best["point"] = result.best_point;
    nlohmann::ordered_json axes = nlohmann::ordered_json::object();
    for (const Axis& a : grid.axes)
        axes[spec.parameters[a.parameter].name] = a.values;
    best["grid"] = axes;
    best["failed"] = result.failed;
    if (!result.simulation.empty()) best["simulation"] = "best/best.xml";
    if (!result.simulation_error.empty()) best["simulation_error"] = result.simulation_error;
    best["command"] = options.command;
    detail::write_file((out / "best.json").string(), detail::json_text(best, 2) + "\n");
    return result;
}

}  // namespace gaitlab::optimize
