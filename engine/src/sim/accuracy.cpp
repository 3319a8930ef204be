#include "gaitlab/accuracy.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "gaitlab/error.h"
#include "gaitlab/simulation.h"

namespace gaitlab {

namespace {

constexpr double kMinPath = 0.001;  // m: a shorter path is judged against 1 mm
constexpr double kMinDt = 1e-6;     // s: validate()'s smallest dt

double horizontal(const Vec3& v) {
    return std::hypot(v.x, v.y);
}

// each robot's run: the path sampled every `cycle` s from `settle` s on (at the nearest
// ticks), and its end
std::vector<AccuracyRun> run(const WorldSpec& world, const SimulationOptions& options,
                             const AccuracyReport& check,
                             const std::function<void(Simulation&)>& prepare,
                             std::vector<std::string>* names) {
    Simulation sim(world, options);
    if (prepare) prepare(sim);
    const long total = sim.ticks_for(check.seconds);
    const int robots = sim.robot_count();
    std::vector<AccuracyRun> out(static_cast<size_t>(robots));
    std::vector<Vec3> last(out.size());
    for (int r = 0; r < robots && names; ++r)
        names->push_back(sim.robot_label(r));
    // the sample ticks: the one nearest to settle + k cycles (so every setting samples at the
    // same times, to within its step), and the end
    for (long k = 0;; ++k) {
        const long to =
            std::min(total, sim.ticks_for(check.settle + static_cast<double>(k) * check.cycle));
        const long ticks = to - sim.ticks();
        if (sim.step(ticks) < ticks) break;  // paused by a controller's failure
        for (int r = 0; r < robots; ++r) {
            const Vec3 now = sim.robot_position(r);
            if (k > 0)
                out[static_cast<size_t>(r)].path += horizontal(now - last[static_cast<size_t>(r)]);
            last[static_cast<size_t>(r)] = now;
        }
        if (to == total) break;
    }
    for (int r = 0; r < robots; ++r) {
        out[static_cast<size_t>(r)].displacement = sim.robot_displacement(r);
        out[static_cast<size_t>(r)].turned = sim.robot_turned(r);
    }
    return out;
}

// the given path minus the finer one, in % of the finer one (of 1 mm if shorter)
double off(const AccuracyRun& given, const AccuracyRun& finer) {
    return 100 * (given.path - finer.path) / std::max(finer.path, kMinPath);
}

// the warning for `setting` if a robot's path is more than the tolerance off the finer run's
void warn(AccuracyReport& report, const std::string& setting, const std::string& finer_setting,
          const std::string& remedy, AccuracyRun AccuracyRobot::*finer,
          double AccuracyRobot::*offset) {
    const AccuracyRobot* worst = nullptr;
    for (const AccuracyRobot& r : report.robots) {
        if (!worst || std::abs(r.*offset) > std::abs(worst->*offset)) worst = &r;
    }
    if (!worst || std::abs(worst->*offset) <= kAccuracyTolerance) return;
    report.warnings.push_back(fmt::format(
        "{}: robot '{}' moves {:.1f} % {} than with {} ({:.1f} against {:.1f} mm from {:g} to "
        "{:g} s, sampled every {:g} s); more than {:g} %, so its speed depends on the setting: "
        "{} (docs/performance.md, \"Which settings for which robot\")",
        setting, worst->name, std::abs(worst->*offset), worst->*offset > 0 ? "faster" : "slower",
        finer_setting, worst->given.path * 1000, (worst->*finer).path * 1000, report.settle,
        report.seconds, report.cycle, kAccuracyTolerance, remedy));
}

}  // namespace

AccuracyReport check_accuracy(const WorldSpec& world, const SimulationOptions& options,
                              double seconds, double cycle, double settle,
                              const std::function<void(Simulation&)>& prepare) {
    validate(options);
    if (!(std::isfinite(seconds) && seconds > 0))
        throw SpecError(fmt::format("the check's seconds must be > 0 (got {:g})", seconds));
    if (!(std::isfinite(settle) && settle >= 0 && settle < seconds)) {
        throw SpecError(
            fmt::format("the check's settle must be in [0, seconds) = [0, {:g}) s "
                        "(got {:g})",
                        seconds, settle));
    }
    if (!(std::isfinite(cycle) && cycle >= options.dt && cycle <= seconds - settle)) {
        throw SpecError(fmt::format(
            "the check's cycle must be in [dt, seconds - settle] = [{:g}, {:g}] s (got {:g})",
            options.dt, seconds - settle, cycle));
    }
    AccuracyReport report;
    report.seconds = seconds;
    report.cycle = cycle;
    report.settle = settle;
    report.given = report.finer_dt = report.more_iterations = options;
    report.dt_checked = options.dt / 4 >= kMinDt && options.control_every <= kMaxControlEvery / 4;
    if (report.dt_checked) {
        report.finer_dt.dt = options.dt / 4;
        report.finer_dt.control_every = options.control_every * 4;
    }
    report.more_iterations.solver_iterations =
        std::min(options.solver_iterations * 4, kMaxSolverIterations);
    // the longest run's ticks must fit (an error before anything runs)
    checked_ticks("the check's seconds", seconds, report.finer_dt.dt);

    std::vector<std::string> names;
    const std::vector<AccuracyRun> given = run(world, options, report, prepare, &names);
    const std::vector<AccuracyRun> finer_dt =
        report.dt_checked ? run(world, report.finer_dt, report, prepare, nullptr) : given;
    const std::vector<AccuracyRun> more =
        run(world, report.more_iterations, report, prepare, nullptr);
    for (size_t r = 0; r < given.size(); ++r) {
        AccuracyRobot robot;
        robot.name = names[r];
        robot.given = given[r];
        robot.finer_dt = finer_dt[r];
        robot.more_iterations = more[r];
        robot.dt_off = off(given[r], finer_dt[r]);
        robot.iterations_off = off(given[r], more[r]);
        report.robots.push_back(std::move(robot));
    }
    if (report.dt_checked) {
        warn(report, fmt::format("dt = {:g} ms", options.dt * 1000),
             fmt::format("dt = {:g} ms", report.finer_dt.dt * 1000),
             fmt::format("take a smaller dt, with control_every scaled to keep the control "
                         "period (dt = {:g} ms, control_every = {})",
                         report.finer_dt.dt * 1000, report.finer_dt.control_every),
             &AccuracyRobot::finer_dt, &AccuracyRobot::dt_off);
    }
    warn(report, fmt::format("solver_iterations = {}", options.solver_iterations),
         fmt::format("solver_iterations = {}", report.more_iterations.solver_iterations),
         "take more iterations", &AccuracyRobot::more_iterations, &AccuracyRobot::iterations_off);
    return report;
}

}  // namespace gaitlab
