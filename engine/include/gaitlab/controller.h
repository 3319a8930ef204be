// The controller kernel: every controller declares named parameters (default, range, unit) that
// can change while it runs, and per-joint values that can be read, recorded and plotted.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/actuation.h"
#include "gaitlab/event.h"
#include "gaitlab/sensor.h"

namespace gaitlab {

/// A named controller parameter.
struct ParamDef {
    std::string name;
    double default_value = 0;
    double min = 0;
    double max = 0;
    std::string unit;  ///< "deg", "Hz", "" ...
};

/// What a controller declares about itself.
struct ControllerDef {
    std::string name;
    std::vector<ParamDef> params;
    std::vector<std::string> values;  ///< per-joint value names, e.g. "time", "angle"
};

/// Checks names, ranges and defaults of a definition; throws SpecError.
void validate(const ControllerDef& def);

/// Measured state of the joints of a controller's group, read on demand.
class JointReader {
  public:
    virtual ~JointReader() = default;
    virtual double angle(int joint) const = 0;     ///< rad
    virtual double velocity(int joint) const = 0;  ///< rad/s
    virtual double torque(int joint) const = 0;    ///< N·m on the head-side body
};

/// The sensors of the robot a controller's group belongs to, numbered k = 0.. in the order
/// of RobotSpec::sensors, read on demand.
class SensorReader {
  public:
    virtual ~SensorReader() = default;
    virtual int count() const = 0;
    /// Sensor k's spec: its name is resolved and `enabled` is its current switch.
    virtual const SensorSpec& spec(int k) const = 0;
    /// Sensor k's latest readings, one per channel of its kind (sensor_channels), engine
    /// units; while the sensor is switched off they keep the values of its last reading.
    virtual const double* values(int k) const = 0;
};

/// The inputs and outputs of one control step for one group. Joint numbers m are 0-based
/// within the group, from the tail.
class ControlIO {
  public:
    /// `sensors` (may be null: no sensors) are those of the group's robot.
    ControlIO(double dt, double time, const std::vector<int>& joints, const JointReader& reader,
              double* targets, const SensorReader* sensors = nullptr)
        : dt_(dt),
          time_(time),
          joints_(joints),
          reader_(reader),
          targets_(targets),
          sensors_(sensors) {}

    double dt() const { return dt_; }      ///< time since the previous control step, s
    double time() const { return time_; }  ///< simulation time, s
    int joints() const { return static_cast<int>(joints_.size()); }
    double angle(int m) const { return reader_.angle(joints_[m]); }
    double velocity(int m) const { return reader_.velocity(joints_[m]); }
    double torque(int m) const { return reader_.torque(joints_[m]); }
    /// Sets joint m's target angle, rad; it holds until the next control step. A target that
    /// is not a finite number throws SpecError (the controller's step fails).
    void set_target(int m, double rad) {
        if (!std::isfinite(rad)) bad_target(m, rad);
        targets_[m] = rad;
    }
    double target(int m) const { return targets_[m]; }

    /// Number of sensors of the group's robot (feedback: see sensor.h).
    int sensor_count() const { return sensors_ ? sensors_->count() : 0; }
    /// Index k of the robot's sensor called `name`, or -1.
    int find_sensor(std::string_view name) const;
    /// Sensor k's spec (resolved name, current switch in `enabled`).
    const SensorSpec& sensor(int k) const { return sensors_->spec(k); }
    /// Sensor k's readings at the start of this tick, one per channel, engine units (radians);
    /// stale (its last reading) while it is switched off.
    const double* sensor_values(int k) const { return sensors_->values(k); }

  private:
    [[noreturn]] void bad_target(int m, double rad) const;
    double dt_;
    double time_;
    const std::vector<int>& joints_;
    const JointReader& reader_;
    double* targets_;
    const SensorReader* sensors_;
};

/// Base of every controller, built in or scripted. A controller drives one joint group.
class Controller {
  public:
    explicit Controller(ControllerDef def);
    virtual ~Controller() = default;
    Controller& operator=(const Controller&) = delete;

    const ControllerDef& def() const { return def_; }
    const std::string& name() const { return def_.name; }

    /// Index of the parameter called `name`, or -1.
    int find_param(std::string_view name) const;
    double param(int i) const { return params_[i]; }
    /// Value of the parameter called `name`; throws SpecError if there is none.
    double param(std::string_view name) const;
    /// Sets parameter i after checking its range; throws SpecError naming the range and unit.
    /// `origin` says who made the change: the simulation driving the controller records it as
    /// an event (see event.h).
    void set_param(int i, double value, Origin origin = Origin::script);
    void set_param(std::string_view name, double value, Origin origin = Origin::script);
    /// Increases whenever a parameter changes.
    std::uint64_t param_version() const { return param_version_; }
    /// Increases whenever the definition changes (a scripted controller's code was reloaded).
    std::uint64_t def_version() const { return def_version_; }

    /// Called after a parameter took a new value, with its index, the value and the origin of
    /// the change; the simulation that drives the controller sets it. One listener at a time.
    using ParamListener = std::function<void(int param, double value, Origin origin)>;
    void set_param_listener(ParamListener fn) { param_listener_ = std::move(fn); }

    /// Number of joints of the group this controller drives (0 until bound).
    int joints() const { return joints_; }
    bool bound() const { return joints_ > 0; }
    /// Attaches the controller to a group of `joints` joints; values start at zero.
    void bind(int joints);
    /// Detaches it from its group when the simulation that bound it is gone (destroyed, or
    /// failed to build): unbound, no values, no listener, parameters kept, so the next
    /// simulation given it binds it itself instead of driving a copy.
    void unbind();
    /// Per-joint value k (as declared in def().values), one entry per joint.
    const std::vector<double>& values(int k) const;
    /// Every per-joint value at once, indexed like def().values (one sync for all of them).
    const std::vector<std::vector<double>>& all_values() const;
    int find_value(std::string_view name) const;

    /// Back to the state just after bind(): values zero, parameters kept.
    virtual void reset();
    /// Whether a step of this controller failed (see SimulationOptions::on_controller_error).
    bool failed() const { return failed_; }
    /// What the failed step reported ("" if none).
    const std::string& failure() const { return failure_; }
    /// Marks the controller failed (its group then holds its position) or, with `failed`
    /// false, running again.
    void set_failed(bool failed, std::string message = {});
    /// Computes the group's targets for this control step.
    virtual void step(ControlIO& io) = 0;
    /// How an actuation file names this controller, with every parameter at its current value.
    /// A built-in is named by name(); throws SpecError for a controller no file can name.
    virtual ControllerRef ref() const;

    /// An independent copy with this controller's whole state: definition, parameters, the
    /// group size it is bound to, per-joint values, failure, and whatever the subclass keeps
    /// (oscillator states, a Lua controller's table). The copy has no parameter listener and
    /// its future steps, given the same inputs, equal this one's bit for bit. Throws
    /// SpecError naming the controller when it cannot be copied (a C++ subclass that does not
    /// override clone(); a Lua controller holding a value that cannot be copied).
    virtual std::unique_ptr<Controller> clone() const;
    /// A copy as a new group would start it: unbound, its parameters at this controller's
    /// current values, not failed (what a second simulation built from the same spec drives
    /// its group with). By default clone() made unbound.
    virtual std::unique_ptr<Controller> fresh_copy() const;

  protected:
    /// Copies the kernel's state (not the parameter listener): for subclasses' copy
    /// constructors, which clone() overrides use.
    Controller(const Controller& other);
    std::vector<double>& value(int k) { return values_[k]; }
    /// Replaces the definition of a bound controller (a scripted controller whose code was
    /// reloaded): `params` holds one value per parameter of `def`, each inside its range. Values
    /// are resized to the new names (zeros); a subclass keeping them elsewhere syncs them.
    void redefine(ControllerDef def, std::vector<double> params);
    /// Brings values_ up to date when a subclass keeps its state elsewhere (e.g. in Lua).
    virtual void sync_values() const {}
    /// Called by bind() and reset() once values are sized and zeroed.
    virtual void on_bind() {}
    mutable std::vector<std::vector<double>> values_;

  private:
    ControllerDef def_;
    std::vector<double> params_;
    std::uint64_t param_version_ = 0;
    std::uint64_t def_version_ = 0;
    ParamListener param_listener_;
    int joints_ = 0;
    bool failed_ = false;
    std::string failure_;
};

}  // namespace gaitlab
