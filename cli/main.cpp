// The gaitlab executable: gaitlab run FILE.lua|FILE.xml (recorded to runs/ by default),
// gaitlab FILE.lua, gaitlab data DIR (list, extract, export, plot recorded series), gaitlab
// replay DIR, --help, --version.
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "gaitlab/error.h"
#include "gaitlab/plot.h"
#include "gaitlab/run_data.h"
#include "gaitlab/scripting/lua_host.h"
#include "gaitlab/scripting/replay.h"
#include "gaitlab/version.h"

namespace {

namespace fs = std::filesystem;

bool ends_with(const std::string& s, const char* suffix) {
    const std::string x(suffix);
    return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

struct RunArgs {
    std::string file;
    std::uint64_t seed = 0;
    std::string record;
    bool no_record = false;
};

int run_script(const RunArgs& a, const std::vector<std::string>& args, const std::string& command) {
    const bool xml = ends_with(a.file, ".xml");
    if (!ends_with(a.file, ".lua") && !xml) {
        std::fprintf(stderr,
                     "gaitlab: %s: expected a Lua script (FILE.lua) or a simulation file "
                     "(FILE.xml)\n",
                     a.file.c_str());
        return 2;
    }
    std::vector<std::string> folders;
    try {
        gaitlab::scripting::LuaHost host;
        // failed reloads of controller files and controllers failing under
        // on_controller_error = "continue" are reported while the script goes on
        host.set_reporter([](const std::string& message) {
            std::fprintf(stderr, "gaitlab: %s\n", message.c_str());
        });
        gaitlab::scripting::RecordSettings rec;
        rec.by_default = true;
        rec.disabled = a.no_record;
        rec.dir = a.record;
        rec.name = fs::path(a.file).stem().string();
        rec.script = a.file;
        rec.command = command;
        host.set_recording(rec);
        host.seed(a.seed);
        host.set_args(a.file, args);
        try {
            if (xml) {
                host.run_simulation_file(a.file);
            } else {
                host.run_file(a.file);
            }
        } catch (const std::exception& e) {
            // the run folders keep the reason; a failed close must not hide it
            try {
                host.finish(e.what());
            } catch (const std::exception&) {
            }
            throw;
        }
        host.finish();
        folders = host.run_folders();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab: %s\n", e.what());
        return 1;
    }
    // one line saying where the runs went
    if (folders.size() == 1) {
        std::fprintf(stderr, "recorded %s\n", folders[0].c_str());
    } else if (!folders.empty()) {
        std::string list;
        for (const std::string& f : folders)
            list += (list.empty() ? "" : ", ") + f;
        std::fprintf(stderr, "recorded %zu runs: %s\n", folders.size(), list.c_str());
    }
    return 0;
}

struct DataArgs {
    std::string dir;
    bool list = false;
    bool events = false;
    std::vector<std::string> series;
    std::string csv;
    std::string split;
    std::string plot;
    std::string title;
    double from = -gaitlab::RunData::kInf;
    double to = gaitlab::RunData::kInf;
};

// "a,b,c" and repeated --series options: one list
std::vector<std::string> split_names(const std::vector<std::string>& given) {
    std::vector<std::string> out;
    for (const std::string& g : given) {
        size_t start = 0;
        for (;;) {
            const size_t comma = g.find(',', start);
            const std::string n =
                g.substr(start, comma == std::string::npos ? comma : comma - start);
            if (!n.empty()) out.push_back(n);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    }
    return out;
}

void print_summary(const gaitlab::RunData& run) {
    const gaitlab::RunMeta& m = run.meta();
    const std::vector<double> t = run.times();
    std::printf("run      %s\n", run.dir().c_str());
    std::printf("status   %s%s%s\n",
                m.status == "running" ? "incomplete (the process ended without closing it)"
                                      : m.status.c_str(),
                m.message.empty() ? "" : ": ", m.message.c_str());
    if (!m.script.empty())
        std::printf("script   %s (seed %llu)\n", m.script.c_str(),
                    static_cast<unsigned long long>(m.script_seed));
    std::printf("started  %s\n", m.started.c_str());
    std::printf("rows     %zu%s, t = %s .. %s s, every %d ticks of %s s\n", t.size(),
                run.truncated() ? " (last line cut short, dropped)" : "",
                t.empty() ? "-" : fmt::format("{}", t.front()).c_str(),
                t.empty() ? "-" : fmt::format("{}", t.back()).c_str(), m.record_every,
                fmt::format("{}", m.options.dt).c_str());
    std::printf("series   %zu (gaitlab data %s --list)\n", run.series().size(), run.dir().c_str());
    std::printf("events   %zu\n", run.events().size());
}

int data_command(const DataArgs& a) {
    try {
        const gaitlab::RunData run(a.dir);
        const std::vector<std::string> wanted = split_names(a.series);
        if (a.list) {
            std::vector<std::string> names = wanted.empty() ? run.names() : run.select(wanted);
            size_t width = 4;
            for (const std::string& n : names)
                width = std::max(width, n.size());
            std::printf("%-*s  %-10s  %-5s  %s\n", static_cast<int>(width), "name", "kind", "joint",
                        "unit");
            for (const std::string& n : names) {
                const gaitlab::SeriesInfo& s = run.find(n);
                std::printf("%-*s  %-10s  %-5s  %s\n", static_cast<int>(width), s.name.c_str(),
                            gaitlab::to_string(s.kind),
                            s.joint > 0 ? std::to_string(s.joint).c_str() : "", s.unit.c_str());
            }
            return 0;
        }
        if (a.events) {
            std::printf("tick,time,origin,kind,name,value,detail\n");
            for (const gaitlab::Event& e : run.events()) {
                std::printf(
                    "%ld,%s,%s,%s,%s,%s,%s\n", e.tick,
                    fmt::format("{}", static_cast<double>(e.tick) * run.meta().options.dt).c_str(),
                    gaitlab::to_string(e.origin), gaitlab::to_string(e.kind), e.name.c_str(),
                    fmt::format("{}", e.value).c_str(), e.detail.c_str());
            }
            return 0;
        }
        if (!a.plot.empty()) {
            if (wanted.empty()) throw gaitlab::SpecError("--plot needs --series NAME[,NAME...]");
            gaitlab::PlotOptions o;
            o.output = a.plot;
            o.series = wanted;
            o.from = a.from;
            o.to = a.to;
            o.title = a.title;
            const gaitlab::PlotFiles f = gaitlab::plot(run, o);
            std::printf("wrote %s (gnuplot script %s, data %s)\n", f.png.c_str(), f.script.c_str(),
                        f.data.c_str());
            return 0;
        }
        if (!wanted.empty()) {
            const std::vector<std::string> names = run.select(wanted);
            if (!a.split.empty()) {
                std::error_code ec;
                fs::create_directories(a.split, ec);
                for (const std::string& n : names) {
                    std::string file = n;
                    for (char& c : file) {
                        if (c == '/' || c == '\\') c = '_';
                    }
                    const std::string path = (fs::path(a.split) / (file + ".csv")).string();
                    run.write_csv(path, {n}, a.from, a.to);
                    std::printf("wrote %s\n", path.c_str());
                }
                return 0;
            }
            if (!a.csv.empty()) {
                run.write_csv(a.csv, names, a.from, a.to);
                return 0;
            }
            // to stdout: the same CSV
            const std::vector<gaitlab::SeriesData> d = run.get(names, a.from, a.to);
            std::string out = "time";
            for (const std::string& n : names)
                out += "," + n;
            out += "\n";
            for (size_t i = 0; i < (d.empty() ? 0 : d[0].time.size()); ++i) {
                out += fmt::format("{}", d[0].time[i]);
                for (const gaitlab::SeriesData& s : d)
                    out += fmt::format(",{}", s.values[i]);
                out += "\n";
            }
            std::fwrite(out.data(), 1, out.size(), stdout);
            return 0;
        }
        if (!a.csv.empty() || !a.split.empty()) {
            throw gaitlab::SpecError("--csv and --split need --series NAME[,NAME...]");
        }
        print_summary(run);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab: %s\n", e.what());
        return 1;
    }
    return 0;
}

int replay_command(const std::string& dir, const std::string& into) {
    try {
        const gaitlab::scripting::ReplayResult r = gaitlab::scripting::replay(dir, into);
        if (!r.script_error.empty()) {
            std::fprintf(stderr, "gaitlab: replay failed: %s\n", r.script_error.c_str());
            return 1;
        }
        if (!r.ok()) {
            std::fprintf(
                stderr, "gaitlab: replay differs: %s\n",
                !r.divergence.empty() ? r.divergence.c_str() : r.comparison.difference.c_str());
            return 1;
        }
        std::printf(
            "replay identical: %ld rows x %zu series, bit for bit%s; %d recorded %s "
            "applied (into %s)\n",
            r.comparison.rows, r.comparison.series,
            r.stopped_early ? " (up to where the run stopped)" : "", r.applied,
            r.applied == 1 ? "change" : "changes", r.into.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gaitlab: %s\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // a file size limit ends a write with an error (reported, data kept), not the process
    std::signal(SIGXFSZ, SIG_IGN);
    std::vector<std::string> argl(argv + 1, argv + argc);
    // "gaitlab FILE.lua ..." is "gaitlab run FILE.lua ..." (and FILE.xml)
    if (!argl.empty() && (ends_with(argl[0], ".lua") || ends_with(argl[0], ".xml"))) {
        argl.insert(argl.begin(), "run");
    }
    std::string command = "gaitlab";
    for (const std::string& a : argl)
        command += " " + a;

    CLI::App app{"gaitlab: simulate modular robots and their locomotion controllers", "gaitlab"};
    app.set_version_flag("--version", std::string("gaitlab ") + gaitlab::version());
    app.require_subcommand(0, 1);

    RunArgs ra;
    CLI::App* run = app.add_subcommand(
        "run", "Run a Lua script, or a simulation file, headless (recorded to runs/)");
    run->add_option("file", ra.file, "The script (FILE.lua) or simulation file (FILE.xml)")
        ->required();
    run->add_option("--seed", ra.seed, "Seed for everything random (math.random too)")
        ->capture_default_str();
    auto* record = run->add_option("--record", ra.record,
                                   "Record into DIR (default: runs/NAME-DATE-TIME; more "
                                   "simulations: DIR-2, DIR-3, ...)");
    record->type_name("DIR");
    auto* no_record =
        run->add_flag("--no-record", ra.no_record, "Record nothing, whatever the script asks");
    record->excludes(no_record);
    // from the first argument after FILE that gaitlab does not know, everything goes to the
    // script, in order (CLI11 leaves it in remaining())
    run->prefix_command();
    run->footer(
        "Arguments after FILE go to the script as arg[1], arg[2], ...\n"
        "Each simulation the script creates is recorded into a run folder (data.csv, "
        "series.csv,\nevents.csv, log.txt, run.json, config/), written every 2 s of wall time; "
        "see docs/data.md.");

    DataArgs da;
    CLI::App* data = app.add_subcommand("data", "List, extract, export or plot recorded series");
    data->add_option("dir", da.dir, "A run folder")->required()->type_name("DIR");
    data->add_flag("--list", da.list, "List the series (name, kind, joint, unit)");
    data->add_flag("--events", da.events, "Print the recorded changes as CSV");
    data->add_option("--series", da.series,
                     "Series to extract, export or plot: names, kinds (robot, controller, "
                     "sensor) or patterns with *, comma-separated")
        ->type_name("NAME[,NAME...]");
    data->add_option("--csv", da.csv, "Write time and the series to this CSV file")
        ->type_name("OUT.csv");
    data->add_option("--split", da.split, "Write each series to its own DIR/NAME.csv")
        ->type_name("DIR");
    data->add_option("--plot", da.plot,
                     "Plot the series into a PNG (gnuplot); OUT.gp and OUT.csv stay next to it")
        ->type_name("OUT.png");
    data->add_option("--title", da.title, "Title of the plot (default: the run's name)");
    data->add_option("--from", da.from, "Only rows at or after this time, s")->type_name("T");
    data->add_option("--to", da.to, "Only rows at or before this time, s")->type_name("T");
    data->footer(
        "Without an option: a summary of the run. With --series only: the series as CSV on "
        "stdout.\nA last line cut short (a killed run) is ignored.");

    std::string replay_dir, replay_into;
    CLI::App* replay = app.add_subcommand(
        "replay",
        "Rerun a recorded run headless and check that it reproduces the data bit for "
        "bit");
    replay->add_option("dir", replay_dir, "The run folder")->required()->type_name("DIR");
    replay->add_option("--into", replay_into, "Record the replay here (default: DIR-replay)")
        ->type_name("DIR");
    replay->footer(
        "The replay runs the script and controller files copied into DIR/config with the "
        "run's\nseed and arguments, and applies the changes the run recorded from the console, "
        "the viewer\nor reloads from disk at their ticks. Exit status 0: identical.");

    std::vector<const char*> args{argv[0]};
    for (const std::string& a : argl)
        args.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(args.size()), args.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // a failure is one line on stderr, like every other failure of gaitlab
        std::fprintf(stderr, "gaitlab: %s (see 'gaitlab --help')\n", e.what());
        return e.get_exit_code();
    }
    if (*run) return run_script(ra, run->remaining(), command);
    if (*data) return data_command(da);
    if (*replay) return replay_command(replay_dir, replay_into);

    std::fputs(app.help().c_str(), stdout);
    std::fputs(
        "\nThe interactive console is not part of this version yet: run a script with\n"
        "'gaitlab run FILE.lua'.\n",
        stdout);
    return argl.empty() ? 2 : 0;
}
