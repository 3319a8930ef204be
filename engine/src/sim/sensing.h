// The sensors of a simulation at run time: where each is mounted, its switch and its latest
// readings. Only the sensors that are switched on are read: the list of them is kept up to
// date when a switch changes, so a switched-off sensor is never visited.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "bullet/sensor_probes.h"
#include "gaitlab/controller.h"
#include "gaitlab/sensor.h"
#include "gaitlab/world.h"

namespace gaitlab {

class PhysicsWorld;

class Sensing {
  public:
    /// Compiles the sensors of every robot of `world` (validated) for a physics step of `dt` s.
    Sensing(const WorldSpec& world, double dt);
    ~Sensing();
    Sensing& operator=(const Sensing&) = delete;

    int count() const { return static_cast<int>(slots_.size()); }
    /// Sensor i's spec with its name resolved; `enabled` is its switch.
    const SensorSpec& spec(int i) const { return slots_[static_cast<size_t>(i)].spec; }
    int robot(int i) const { return slots_[static_cast<size_t>(i)].robot; }
    /// Its index among its robot's sensors (RobotSpec::sensors).
    int local_index(int i) const { return slots_[static_cast<size_t>(i)].local; }
    const std::vector<double>& values(int i) const { return slots_[static_cast<size_t>(i)].values; }
    /// Global index of robot r's k-th sensor.
    int index(int robot, int k) const {
        return robots_[static_cast<size_t>(robot)].sensors[static_cast<size_t>(k)];
    }
    int robot_sensor_count(int robot) const {
        return static_cast<int>(robots_[static_cast<size_t>(robot)].sensors.size());
    }
    /// Index of robot r's sensor called `name`, or -1.
    int find(int robot, std::string_view name) const;
    /// The sensors of robot r as a controller reads them.
    const SensorReader& reader(int robot) const {
        return *robots_[static_cast<size_t>(robot)].reader;
    }
    /// How many sensors are switched on.
    int active_count() const { return static_cast<int>(active_.size()); }

    /// Adds a sensor (validated) to robot r; returns its index. It reads at once if it is on.
    int add(int robot, const SensorSpec& spec, const PhysicsWorld& physics);
    /// Switches sensor i on or off; switching on reads it at once.
    void set_enabled(int i, bool on, const PhysicsWorld& physics);
    /// A new physics world (built or rebuilt): IMU accelerations restart from rest, and every
    /// sensor that is on reads the new state.
    void attach(PhysicsWorld& physics);
    /// An independent copy: the same sensors, switches, readings and IMU history (for a copy
    /// of the simulation; give it its physics world with adopt()).
    std::unique_ptr<Sensing> copy() const;
    /// A physics world that continues the state of the one before (a copy's, or the original
    /// rebuilt by a copy): readings and IMU history are kept.
    void adopt(PhysicsWorld& physics);
    /// The physics steps at `dt` from now on (a copy at another dt): the IMU's next reading
    /// takes the change of velocity over it.
    void set_dt(double dt) { dt_ = dt; }
    /// Reads every sensor that is on; called once per tick, after the physics step.
    void update(const PhysicsWorld& physics);

  private:
    struct Slot {
        SensorSpec spec;
        int robot = 0;
        int local = 0;
        int body = -1;   // imu, range: global body the sensor is mounted on
        int joint = -1;  // joint: the joint; contact: the module's joint (global indices)
        Vec3 direction;  // range: unit vector in the body frame
        std::vector<double> values;
        Vec3 last_velocity;  // imu: body velocity at the previous reading, m/s
        bool has_last = false;
    };
    struct RobotInfo {
        int first_body = 0;
        int bodies = 0;
        int first_joint = 0;
        std::vector<double> masses;
        double total_mass = 0;
        std::vector<int> parents, children;  // per joint of the robot: global body indices
        std::vector<int> sensors;            // global indices, in RobotSpec::sensors order
        std::unique_ptr<SensorReader> reader;
    };
    // a joint of a body: its pivot in the body's frame
    struct BodyJoint {
        Vec3 pivot;
        int joint;
    };
    class Reader;
    Sensing(const Sensing& other);

    Slot compile(int robot, int local, const SensorSpec& spec) const;
    void rebuild_active();
    void read(Slot& s, const PhysicsWorld& physics);
    void read_contacts(const PhysicsWorld& physics);

    double dt_;
    Vec3 gravity_;
    std::vector<Slot> slots_;
    std::vector<RobotInfo> robots_;
    std::vector<std::vector<BodyJoint>> body_joints_;  // per global robot body
    int robot_bodies_ = 0;
    std::vector<int> active_;  // sensors that are on, by index; contact sensors excluded
    std::vector<int> active_contacts_;
    std::vector<std::vector<int>> contacts_by_joint_;  // active contact sensors per module
    std::vector<char> contact_bodies_;                 // bodies those sensors watch
    std::vector<BodyContact> contact_buffer_;
};

}  // namespace gaitlab
