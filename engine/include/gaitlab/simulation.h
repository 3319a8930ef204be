// A simulation: a compiled world, its physics state, its controllers and the scheduler that
// steps them. Compiling validates the spec; reset() rebuilds the physics from it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "gaitlab/error.h"
#include "gaitlab/event.h"
#include "gaitlab/options.h"
#include "gaitlab/scheduler.h"
#include "gaitlab/sensor.h"
#include "gaitlab/types.h"
#include "gaitlab/world.h"

namespace gaitlab {

class Controller;

/// Measured and commanded state of one joint.
struct JointState {
    double angle = 0;     ///< rad, measured
    double target = 0;    ///< rad, commanded (sum of the groups driving it, clamped to range)
    double velocity = 0;  ///< rad/s
    double torque = 0;    ///< N·m applied by the servo (and the range stops) to the head side
};

class PhysicsWorld;
class Sensing;

/// The newton_steps a simulation of `world` with `solver` takes when they are not given
/// (kAutomaticNewtonSteps): kLongChainNewtonSteps with block_nncg where a robot has pitch and
/// yaw joints both and more than kLongChainJoints joints (a pitch-yaw chain of 13 modules or
/// more, whose motions 20 iterations alone do not converge: docs/performance.md, section 12,
/// "Upright or on its side"), 0 otherwise.
int automatic_newton_steps(const WorldSpec& world, ConstraintSolver solver);

class Simulation {
  public:
    /// Validates and compiles `world`; throws SpecError. A controller of `world` that
    /// already drives a group of another simulation (built earlier from the same spec) is not
    /// shared: this simulation drives that group with a fresh copy of it
    /// (Controller::fresh_copy: parameters at their current values, state as just bound), so
    /// one spec builds any number of simulations. The same controller object given to two
    /// groups of `world` is an error, as before.
    Simulation(WorldSpec world, SimulationOptions options = default_simulation_options());
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    const WorldSpec& world() const { return world_; }
    /// What compiling found suspect but not wrong, for the host to show: a robot that starts
    /// more than 5 mm deep inside the floor, an object or another robot (the contact solver
    /// throws it out, often metres away), settings that cannot keep a gait's speed. Running adds
    /// one more, once, with the warning handler called: a robot whose bodies do not collide
    /// with each other (self_collision off) passing through itself, one body more than 5 mm
    /// inside another.
    const std::vector<std::string>& warnings() const { return warnings_; }
    /// Called with each warning running adds to warnings(), from inside the tick that found it.
    using WarningHandler = std::function<void(const std::string&)>;
    void set_warning_handler(WarningHandler fn) { on_warning_ = std::move(fn); }
    /// The options it runs with: those given, with newton_steps chosen for the world where it
    /// was kAutomaticNewtonSteps (automatic_newton_steps)
    const SimulationOptions& options() const { return options_; }
    /// The options as a simulation file should give them: options(), with newton_steps left to
    /// the world (kAutomaticNewtonSteps) where they are the world's own choice, so that the file
    /// chooses them again and one given otherwise (0 included) is kept
    SimulationOptions written_options() const;
    long ticks() const { return scheduler_.ticks(); }
    double time() const { return scheduler_.time(); }

    /// Advances `ticks` ticks, in [0, kMaxTicks - ticks()] (SpecError otherwise; see
    /// scheduler.h for the order inside one tick); the pre-tick
    /// hooks run before each of them. Between ticks only: from inside a tick (a controller, an
    /// observer, a hook or an event listener) it throws SpecError. Under
    /// ControllerErrorPolicy::pause it returns early, at
    /// the end of the tick in which a controller failed; returns the number of ticks run.
    long step(long ticks = 1);
    /// Advances round(seconds / dt) ticks (fewer if paused); returns the ticks run. `seconds`
    /// must be such that the run stays within kMaxTicks in all (SpecError naming the range).
    long run(double seconds);
    /// The ticks run(seconds) would advance: round(seconds / dt), checked as run checks it.
    long ticks_for(double seconds) const;
    /// Whether the last step/run returned early because a controller failed under
    /// ControllerErrorPolicy::pause; the next step/run clears it.
    bool paused() const { return paused_; }
    /// Rebuilds the physics from the spec, time 0, controllers reset (parameters kept); posts
    /// a reset event stamped with the tick it happened at. Between ticks or from a pre-tick
    /// hook only (SpecError otherwise).
    void reset(Origin origin = Origin::script);

    /// An independent copy of the simulation as it stands: spec, time and tick counter, every
    /// body's and joint's state, the contact solver's warm-start state, servo commands,
    /// controllers with all their state (Controller::clone), sensors with their switches,
    /// readings and filters, robot headings, the paused flag. Given the same inputs from now
    /// on, the copy and the original step bit-identically: the original continues in a physics
    /// world rebuilt exactly as the copy's is (PhysicsWorld::copy_state_from), so both hold
    /// the same Bullet state down to the order of contact pairs and manifolds.
    ///
    /// Not copied: observers, pre-tick hooks, event listeners and the controller error
    /// handler (they belong to whoever added them: add them to the copy). The copy shares no
    /// mutable state with the original and may step on another thread, as long as its
    /// controllers may (built-in ones may; a Lua controller's copy lives in the same Lua state
    /// as its original and steps on that state's thread).
    ///
    /// Between ticks only (SpecError from inside a tick). Throws SpecError naming a
    /// controller that cannot be copied, and whatever rebuilding the physics throws (a
    /// heightfield image that can no longer be read); the original is then unchanged.
    std::unique_ptr<Simulation> clone();

    /// A copy as clone() makes that steps from now on with `settings`' dt, control_every,
    /// solver_iterations, solver and newton_steps (kAutomaticNewtonSteps: chosen for the world
    /// as a new simulation does); its other options are this simulation's. What it is for: a
    /// motion the robot has settled into, continued at finer settings, to see whether the
    /// motion itself converges (docs/performance.md, "A motion continued at finer settings").
    /// The control period (dt x control_every) must stay as it is, and the time must be a
    /// whole number of the new dt; the warm-start impulses are scaled to the new dt (the same
    /// forces). With the same settings the copy is clone()'s, bit for bit. Throws SpecError
    /// naming the setting that cannot be taken (the original unchanged), and what clone()
    /// throws.
    std::unique_ptr<Simulation> clone(const SimulationOptions& settings);

    /// Adds a drive to robot r while the simulation exists; throws SpecError. After time 0 it
    /// posts a drive event.
    void add_drive(int robot, Drive drive, Origin origin = Origin::script);

    int robot_count() const { return static_cast<int>(world_.robots.size()); }
    /// The robot's name, made unique within the simulation ("snake", "snake_2", ...): series
    /// names start with it.
    const std::string& robot_label(int robot) const;

    /// Drives in the order they were added (robot by robot for those of the spec).
    int drive_count() const { return static_cast<int>(drives_.size()); }
    const Controller& controller(int drive) const;
    Controller& controller(int drive);
    /// The robot a drive belongs to.
    int drive_robot(int drive) const;
    /// Its joints, 0-based indices into the robot's joints, in group order.
    const std::vector<int>& drive_joints(int drive) const;
    /// The controller's name, made unique within the simulation (among robot labels too): the
    /// second controller called "sine" is "sine_2", the third "sine_3". Labels never change
    /// once given.
    const std::string& drive_label(int drive) const;
    /// Centre of mass of robot r, m.
    Vec3 robot_position(int robot) const;
    /// Velocity of robot r's centre of mass, m/s.
    Vec3 robot_velocity(int robot) const;
    /// Centre of mass minus its value at time 0, m.
    Vec3 robot_displacement(int robot) const;
    /// Heading of robot r, rad in (-π, π]: the direction of the line from the centre of its
    /// tail body (its first body) to that of its head body (its last body), projected on the
    /// floor plane, from +x towards +y (counter-clockwise seen from +z). When that line is
    /// (almost) vertical, the tail body's x axis gives the direction; when that is vertical
    /// too, the last heading is kept.
    double robot_heading(int robot) const;
    /// How far robot r has turned since time 0, rad, counter-clockwise positive, not wrapped
    /// (two turns to the left read 4π): the heading followed tick by tick, so a turn of any
    /// size is counted as long as it turns less than half a turn per tick.
    double robot_turned(int robot) const;
    BodyState body(int robot, int body) const;
    JointState joint(int robot, int joint) const;
    /// Mechanical power of every servo of robot r, torque × velocity, W, into
    /// out[0 .. joints) (cheaper than joint() for each).
    void joint_powers(int robot, double* out) const;
    /// Energy every servo of robot r has spent since time 0, J, into out[0 .. joints): the
    /// integral of |torque × velocity| dt, summed at every physics step by the simulation
    /// itself (whether anything records it or not). clone() copies it; reset() sets it to 0.
    void joint_energies(int robot, double* out) const;
    /// The sum of joint_energies over robot r's joints, in joint order (the recorded
    /// ROBOT.energy series), J.
    double robot_energy(int robot) const;
    JointError joint_error(int robot, int joint) const;
    /// Number of dynamic objects of the world (boxes and cylinders with mass > 0).
    int object_count() const;
    /// State of dynamic object `index` (from 0, in the order of world_solids(): boxes first,
    /// then cylinders, each in spec order).
    BodyState object(int index) const;
    /// Contact points in the last physics step.
    int contact_count() const;
    /// The contact points of the last physics step closer than 1 mm, into `out` (cleared first).
    void contacts(std::vector<ContactPoint>& out) const;

    // Sensors (sensor.h, docs/sensors.md). They are numbered 0.. over the whole simulation:
    // robot by robot in the order of their specs' sensors, then those added later. Readings
    // describe the state at time(): each sensor that is on is read once per tick, right after
    // the physics step (so record observers, and callers between steps, see the new state, and
    // the next tick's think sees the same values), and when the simulation is built or reset,
    // and when it is added or switched on. A sensor that is off is not visited at all.

    int sensor_count() const;
    /// Sensor i's spec: its name resolved, `enabled` its current switch.
    const SensorSpec& sensor(int i) const;
    /// The robot sensor i belongs to.
    int sensor_robot(int i) const;
    /// Index of robot r's sensor called `name`, or -1.
    int find_sensor(int robot, std::string_view name) const;
    /// Index of robot r's k-th sensor (RobotSpec::sensors order).
    int sensor_index(int robot, int k) const;
    /// The names and engine units of sensor i's values (sensor_channels of its kind).
    const std::vector<SensorChannel>& sensor_channels(int i) const;
    /// Sensor i's latest readings, one per channel, engine units (rad, rad/s, m ...). While it
    /// is switched off they keep the values of its last reading.
    const std::vector<double>& sensor_values(int i) const;
    bool sensor_enabled(int i) const;
    /// Switches sensor i on (it reads at once, then every tick) or off (no more readings, no
    /// cost); kept by reset() and in world().
    /// Posts a sensor event ("<robot label>.<sensor>", 1 or 0) when the switch changes.
    void set_sensor_enabled(int i, bool on, Origin origin = Origin::script);
    /// Index of the sensor "<robot label>.<sensor name>" (as events name it), or -1.
    int find_sensor(std::string_view label) const;
    /// Attaches a sensor to robot r while the simulation exists; returns its index. Throws
    /// SpecError (see validate_sensor).
    int add_sensor(int robot, SensorSpec sensor);

    /// Called when a controller fails under ControllerErrorPolicy::continue_ or pause, once per
    /// failure, with the exception its step threw.
    using ControllerErrorHandler = std::function<void(const Controller&, const std::exception&)>;
    void set_controller_error_handler(ControllerErrorHandler fn) { on_error_ = std::move(fn); }

    // Callbacks (observers, pre-tick hooks, event listeners, controllers) may add and remove
    // callbacks and drives, and attach sensors, while the simulation runs them: what they add
    // acts from the next time its list is walked (a drive from the next control tick), what
    // they remove is not called again. They must not step or run the simulation that calls
    // them, nor reset it except from a pre-tick hook (SpecError "cannot step the simulation
    // from inside its own tick (...)").

    /// Calls `fn` in the record phase of every tick; returns an id for remove_observer.
    int add_observer(std::function<void(const Simulation&)> fn);
    void remove_observer(int id);

    /// Calls `fn` before every tick, between ticks: the place where changes from outside the
    /// script (console, viewer, replay) are applied, so they act from that tick on. Returns an
    /// id for remove_pre_tick.
    int add_pre_tick(std::function<void(Simulation&)> fn);
    void remove_pre_tick(int id);

    /// Calls `fn` for every event (parameter changes of its controllers, resets, ...), in the
    /// order they happen; returns an id for remove_event_listener.
    int add_event_listener(std::function<void(const Simulation&, const Event&)> fn);
    void remove_event_listener(int id);
    /// Stamps `event` with the current tick and hands it to every listener.
    void post_event(Event event);

  private:
    struct Copying {};
    // the copy clone() makes (its physics copies `from`'s current world), stepping with
    // `options` (clone(settings): checked, the same control period and time)
    Simulation(const Simulation& from, Copying, const SimulationOptions& options);
    // reports parameter changes of drive `index`'s controller as events of this simulation
    void listen(int index);
    class Phases;
    struct RobotSlot {
        int first_body = 0;
        int first_joint = 0;
        Vec3 start_position;
        std::string label;
        double heading = 0;  // rad, at the last tick (see robot_heading)
        double turned = 0;   // rad, unwrapped, since time 0
    };
    // robot r's heading now, or `previous` when it has none (upright robot)
    double heading_now(int robot, double previous) const;
    // follows every robot's heading; at time 0 (build) `start` sets turned to 0
    void track_headings(bool start);
    // adds every servo's |power| dt of the step just taken to energy_
    void integrate_energy();
    struct DriveSlot {
        int robot;
        Drive drive;
        std::vector<int> global_joints;
        std::vector<double> targets;
        std::string label;
    };

    // what the constructor does once the spec is valid
    void compile();
    // (re)builds the physics from the spec
    void build();
    // "not enough memory to build the simulation (...)", for a std::bad_alloc while building
    Error out_of_memory() const;
    // unbinds every controller it drives (they may outlive it: a script holds them)
    void release_controllers();
    void check_robot(int robot) const;
    void check_sensor(int sensor) const;
    void check_drive(int drive) const;
    void dispatch(const Event& event);
    std::string unique_label(const std::string& base);
    // "body 'tail' of robot 'snake'", "box 2": how messages name physics body `body`
    std::string body_name(int body) const;
    // the robot (index) physics body `body` belongs to, for a robot's body
    size_t robot_of_body(int body) const;
    // warns if a robot starts deep inside the floor, an object or another robot
    void check_start_overlaps();
    // warns if a body is heavy enough to sink a large part of its height into the compliant
    // floor
    void check_floor_sinking();
    // warns, once, if a robot whose bodies do not collide with each other passes through
    // itself in the state as it stands (`time`: its time)
    void check_self_pass(double time);
    std::vector<std::string> warnings_;
    // ticks between checks whether a robot passes through itself; 0: none (no robot can, or
    // one did and got its warning)
    long self_pass_every_ = 0;
    bool self_pass_warned_ = false;
    // throws DivergenceError naming physics body `body` (it diverged in the step to `time`)
    [[noreturn]] void diverged(int body, double time) const;
    // marks the drive's controller failed and freezes its targets at the measured angles
    void fail(DriveSlot& d, const std::exception& e);

    WorldSpec world_;
    SimulationOptions options_;
    Scheduler scheduler_;
    std::unique_ptr<PhysicsWorld> physics_;
    std::unique_ptr<Sensing> sensing_;
    std::unique_ptr<Phases> phases_;
    std::vector<RobotSlot> robots_;
    int first_object_ = 0;  // index of the first dynamic object among the physics' bodies
    // a deque: a controller may add a drive while its own slot is in use (think walks the
    // drives by index and keeps references), and a deque keeps existing elements in place
    std::deque<DriveSlot> drives_;
    std::vector<double> angles_;    // per global joint, rad, read in sense
    std::vector<double> targets_;   // per global joint, rad, summed in think
    std::vector<double> commands_;  // per global joint, rad/s, computed in act
    std::vector<double> energy_;    // per global joint, J, ∫ |torque × velocity| dt since time 0
    // A list of callbacks that the callbacks themselves may change while it is walked: those
    // added during a walk wait in `added_` and removed ones are only marked, until the next
    // walk that starts outside any other (walks nest when a listener posts an event).
    template <class Fn>
    class Callbacks {
      public:
        void add(int id, Fn fn) {
            (walking_ > 0 ? added_ : list_).push_back({id, true, std::move(fn)});
            changed_ = true;
        }
        void remove(int id) {
            for (auto* list : {&list_, &added_}) {
                for (Entry& e : *list) {
                    if (e.id == id) e.live = false;
                }
            }
            changed_ = true;
        }
        bool idle() const { return list_.empty() && !changed_; }
        template <class... Args>
        void call(Args&... args) {
            if (changed_ && walking_ == 0) tidy();
            ++walking_;
            struct Leave {
                int& walking;
                ~Leave() { --walking; }
            } leave{walking_};
            // by index: nothing is added to list_ during the walk, but stay safe if it were
            for (size_t i = 0; i < list_.size(); ++i) {
                if (list_[i].live) list_[i].fn(args...);
            }
        }

      private:
        struct Entry {
            int id;
            bool live;
            Fn fn;
        };
        void tidy() {
            changed_ = false;
            for (Entry& e : added_)
                list_.push_back(std::move(e));
            added_.clear();
            list_.erase(
                std::remove_if(list_.begin(), list_.end(), [](const Entry& e) { return !e.live; }),
                list_.end());
        }
        std::vector<Entry> list_, added_;
        int walking_ = 0;
        bool changed_ = false;
    };
    // what the simulation is running now (a controller's step, an observer, ...), or null
    // between ticks: step, run and reset refuse to start while it is set
    class Busy;
    void check_idle(const char* what) const;
    const char* busy_ = nullptr;

    Callbacks<std::function<void(const Simulation&)>> observers_;
    Callbacks<std::function<void(Simulation&)>> pre_ticks_;
    Callbacks<std::function<void(const Simulation&, const Event&)>> listeners_;
    int next_observer_ = 1;
    std::set<std::string> labels_;
    ControllerErrorHandler on_error_;
    WarningHandler on_warning_;
    bool pause_pending_ = false;  // a controller failed under the pause policy in this tick
    bool paused_ = false;
};

}  // namespace gaitlab
