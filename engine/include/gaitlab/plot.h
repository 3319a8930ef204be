// Plots of recorded series as PNG, drawn by gnuplot (pngcairo). The gnuplot script and the data
// it plots are kept next to the PNG, so the plot can be edited and redrawn by hand.
#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace gaitlab {

class RunData;

/// What to plot and where.
struct PlotOptions {
    /// the PNG to write, e.g. "walk.png"; "walk.gp" (the script) and "walk.csv" (its data) go
    /// next to it
    std::string output;
    std::vector<std::string> series;  ///< names, kinds or '*' patterns (RunData::select)
    /// A path plot instead of series against time: `y` against `x` (one series each, `series`
    /// left empty), e.g. "snake.com.x" and "snake.com.y" for a robot's path seen from above;
    /// the axes have one scale when the two series have one unit.
    std::string x, y;
    double from = -std::numeric_limits<double>::infinity();  ///< s
    double to = std::numeric_limits<double>::infinity();     ///< s
    std::string title;                                       ///< "" : the run's name
    int width = 1000;                                        ///< pixels
    int height = 600;                                        ///< pixels
};

/// The files a plot wrote.
struct PlotFiles {
    std::string png, script, data;
};

/// Writes the data and the gnuplot script, then runs `gnuplot` on it. Throws SpecError (bad
/// options or series names, with suggestions; a path plot whose x or y selects several series
/// or has no numbers in the time range) or IoError (files, or gnuplot missing or failing: the
/// script and data stay, to run by hand).
PlotFiles plot(const RunData& run, const PlotOptions& options);

/// `s` as a gnuplot string literal, whatever its bytes (every byte but letters, digits and a few
/// punctuation marks as an octal escape): for scripts that hold file names, titles, labels.
std::string gp_string(std::string_view s);

/// Runs `gnuplot SCRIPT` in the folder `dir` (no shell; gnuplot's output to /dev/null); returns
/// "" or what went wrong ("cannot run gnuplot (install the gnuplot-nox package)", "gnuplot
/// failed: ITS MESSAGE").
std::string run_gnuplot(const std::filesystem::path& dir, const std::string& script);
/// A line plot of columns against the first one (not against time), e.g. an optimization's
/// generation against its best and mean fitness.
struct TablePlot {
    std::string output;  ///< the PNG to write; NAME.gp and NAME.csv go next to it
    std::string title, xlabel, ylabel;
    std::vector<std::string> columns;       ///< x first, then one curve each; at least two
    std::vector<std::vector<double>> rows;  ///< one value per column; NaN: no point there
    int width = 1000;                       ///< pixels
    int height = 600;                       ///< pixels
};

/// Writes the data and the gnuplot script, then runs `gnuplot` on it, as plot() does. Throws
/// SpecError (a bad output name, fewer than two columns, a row of another length) or IoError.
PlotFiles plot_table(const TablePlot& table);

}  // namespace gaitlab
