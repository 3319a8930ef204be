// Series: the named, sampled quantities of a simulation that the recorder writes and the live
// buffers keep. They come from sources: the robots (poses, centre of mass, joints, power and
// energy), the controllers (parameters and per-joint values), the sensors (every channel) and
// the world's moving objects (their poses).
// docs/data.md lists every name.
//
// Naming: "<label>.<quantity>" with a 1-based joint in brackets for per-joint quantities:
//   robot       snake.com.x  snake.com.vx  snake.head.qw  snake.angle[3]  snake.power
//   snake.energy[2] controller  sine.amplitude  sine.angle[3]  hopf.x[3]   (joint numbers within
//   the group)   sensor  snake.imu3.roll  snake.contact1.force  snake.joint2.angle
//   object      box_2.x  box_2.qw  cylinder_1.z  (the object's name, spaces as '_')
// Labels are the robot and controller names made unique within a simulation
// (Simulation::robot_label, Simulation::drive_label): a second "sine" is "sine_2".
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace gaitlab {

class Simulation;

/// Where a series comes from.
enum class SeriesKind { robot, controller, sensor, object };

/// "robot", "controller", "sensor", "object".
const char* to_string(SeriesKind kind);
/// Parses a kind name; returns false if it is not one.
bool parse_series_kind(std::string_view name, SeriesKind& kind);

/// What a series is. One row of a run folder's series.csv.
struct SeriesInfo {
    std::string name;  ///< unique within the simulation, e.g. "snake.angle[3]"
    SeriesKind kind = SeriesKind::robot;
    std::string source;  ///< robot or controller label ("snake", "sine_2"), or object ("box 2")
    std::string value;   ///< the quantity: "angle", "com.x", "x", "amplitude" ...
    int joint = 0;       ///< 1-based joint (within the group for controllers); 0: none
    std::string body;    ///< body name for body poses, "" otherwise
    std::string unit;    ///< "deg", "m", "N·m", "" ...
};

/// A producer of series. Sources are made when a recording or a live buffer starts; their list
/// of series is then fixed.
class SeriesSource {
  public:
    virtual ~SeriesSource() = default;
    /// The series this source fills, in the order sample() writes them.
    virtual const std::vector<SeriesInfo>& series() const = 0;
    /// Called in the record phase of every tick, for quantities that integrate over time.
    virtual void tick(const Simulation&) {}
    /// Writes the current value of every series into out[0 .. series().size()).
    virtual void sample(const Simulation& sim, double* out) = 0;
    /// The simulation was reset to time 0: integrals start again.
    virtual void restart() {}
};

/// The sources of every kind for `sim`: one per robot, one per drive, one per robot with
/// sensors, one for the moving objects if there are any (docs/data.md, "Adding a kind of
/// series", says how to add a kind).
std::vector<std::unique_ptr<SeriesSource>> make_sources(const Simulation& sim);

/// Does `name` match `pattern`? '*' matches any run of characters, '?' one character; every
/// other character matches itself ('[' included).
bool glob_match(std::string_view pattern, std::string_view name);

/// The sources of a simulation and a selection of their series, sampled together.
class SeriesSet {
  public:
    /// All series of `sim` (make_sources), restricted to `selection` when it is not empty: each
    /// entry is a kind ("robot", "controller", "sensor") or a name pattern (glob_match). An
    /// entry that selects nothing throws SpecError naming the closest series.
    SeriesSet(const Simulation& sim, const std::vector<std::string>& selection = {});
    /// The same from explicit sources (tests, custom sources).
    SeriesSet(std::vector<std::unique_ptr<SeriesSource>> sources,
              const std::vector<std::string>& selection);

    /// The selected series, in sampling order.
    const std::vector<SeriesInfo>& series() const { return selected_; }
    size_t size() const { return selected_.size(); }
    /// Index of a selected series by name, or -1.
    int find(std::string_view name) const;

    /// Every tick, in the record phase (integrals).
    void tick(const Simulation& sim);
    /// The selected values now, into out[0 .. size()).
    void sample(const Simulation& sim, double* out);
    void restart();

  private:
    void select(const std::vector<std::string>& selection);

    std::vector<std::unique_ptr<SeriesSource>> sources_;
    std::vector<SeriesInfo> selected_;
    // per source: whether it has a selected series, and the positions in its output that are
    // selected (empty with `all_` set: every one)
    struct Pick {
        bool used = false;
        bool all = false;
        std::vector<int> columns;
    };
    std::vector<Pick> picks_;
    std::vector<double> scratch_;
};

}  // namespace gaitlab
