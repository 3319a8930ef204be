#include "gaitlab/plot.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "data/files.h"
#include "gaitlab/error.h"
#include "gaitlab/files.h"
#include "gaitlab/run_data.h"

namespace gaitlab {

namespace fs = std::filesystem;

namespace {

// a gnuplot double-quoted string
std::string gp_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

// runs `gnuplot SCRIPT` in `dir`; returns "" or what went wrong
std::string run_gnuplot(const fs::path& dir, const std::string& script) {
    int err[2];
    if (pipe(err) != 0) return fmt::format("cannot start gnuplot: {}", data::reason(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        close(err[0]);
        close(err[1]);
        return fmt::format("cannot start gnuplot: {}", data::reason(errno));
    }
    if (pid == 0) {
        dup2(err[1], STDERR_FILENO);
        const int null = open("/dev/null", O_RDWR);
        if (null >= 0) {
            dup2(null, STDIN_FILENO);
            dup2(null, STDOUT_FILENO);
        }
        close(err[0]);
        close(err[1]);
        if (chdir(dir.c_str()) != 0) _exit(126);
        execlp("gnuplot", "gnuplot", script.c_str(), static_cast<char*>(nullptr));
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
        // gnuplot's own message, on one line
        std::string first;
        for (char c : messages) {
            if (c == '\n') {
                if (!first.empty() && first.find_first_not_of(" ^") != std::string::npos &&
                    first.find_first_not_of(' ') != std::string::npos)
                    break;
                first.clear();
                continue;
            }
            first += c;
        }
        return fmt::format("gnuplot failed{}{}", first.empty() ? "" : ": ", first);
    }
    return "";
}

}  // namespace

PlotFiles plot(const RunData& run, const PlotOptions& o) {
    const fs::path png(o.output);
    if (png.extension() != ".png" || png.stem().empty()) {
        throw SpecError(fmt::format("plot output must be a .png file (got '{}')", o.output));
    }
    if (o.series.empty()) throw SpecError("nothing to plot: give at least one series");
    if (o.width < 100 || o.width > 10000 || o.height < 100 || o.height > 10000) {
        throw SpecError(fmt::format("plot size must be 100 to 10000 pixels each way (got {}x{})",
                                    o.width, o.height));
    }
    const std::vector<std::string> names = run.select(o.series);
    PlotFiles files;
    files.png = o.output;
    files.script = (png.parent_path() / (png.stem().string() + ".gp")).string();
    files.data = (png.parent_path() / (png.stem().string() + ".csv")).string();
    std::error_code ec;
    if (!png.parent_path().empty()) fs::create_directories(png.parent_path(), ec);
    run.write_csv(files.data, names, o.from, o.to);

    std::vector<std::string> units;
    for (const std::string& n : names) {
        const std::string& u = run.find(n).unit;
        if (!u.empty() && std::find(units.begin(), units.end(), u) == units.end())
            units.push_back(u);
    }
    std::string gp = fmt::format(
        "# gaitlab plot of run {}: edit this file, then run 'gnuplot {}' in this folder to\n"
        "# redraw {} from {} (time in column 1, then one column per series)\n",
        run.meta().name, png.stem().string() + ".gp", png.filename().string(),
        png.stem().string() + ".csv");
    gp += fmt::format("set terminal pngcairo size {},{} noenhanced font \"sans,10\"\n", o.width,
                      o.height);
    gp += "set output " + gp_string(png.filename().string()) + "\n";
    gp += "set datafile separator \",\"\n";
    gp += "set key outside right top\nset grid\n";
    gp += "set title " + gp_string(o.title.empty() ? run.meta().name : o.title) + "\n";
    gp += "set xlabel \"time (s)\"\n";
    std::string ylabel;
    for (size_t i = 0; i < units.size(); ++i)
        ylabel += (i > 0 ? ", " : "") + units[i];
    gp += "set ylabel " + gp_string(ylabel) + "\n";
    const std::string data_name = gp_string(png.stem().string() + ".csv");
    for (size_t i = 0; i < names.size(); ++i) {
        const std::string& u = run.find(names[i]).unit;
        const std::string title = u.empty() ? names[i] : names[i] + " (" + u + ")";
        gp += i == 0 ? "plot " : ", \\\n     ";
        gp += fmt::format("{} using 1:{} skip 1 with lines title {}", i == 0 ? data_name : "\"\"",
                          i + 2, gp_string(title));
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
