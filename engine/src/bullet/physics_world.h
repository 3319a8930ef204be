// The Bullet side of a simulation. Only this folder includes Bullet headers; this interface
// speaks gaitlab types. Bodies are numbered robot by robot (in WorldSpec order) and then the
// dynamic objects (in world_solids order); joints robot by robot.
#pragma once

#include <memory>

#include "gaitlab/simulation.h"
#include "gaitlab/world.h"

class btDiscreteDynamicsWorld;
class btRigidBody;

namespace gaitlab {

/// "3.24": the version of the Bullet library this engine was built with.
const char* physics_version();

class PhysicsWorld {
  public:
    /// Builds the Bullet scene for `world`; `dt` sets the servo torque limits as impulses.
    /// Throws SpecError if a heightfield's image cannot be read.
    PhysicsWorld(const WorldSpec& world, double dt, int solver_iterations);
    ~PhysicsWorld();
    PhysicsWorld(const PhysicsWorld&) = delete;
    PhysicsWorld& operator=(const PhysicsWorld&) = delete;

    int body_count() const;
    int joint_count() const;

    /// Measured angle of every joint, rad, into out[0 .. joint_count).
    void read_angles(double* out) const;
    double angle(int joint) const;     ///< rad
    double velocity(int joint) const;  ///< rad/s
    double torque(int joint) const;    ///< N·m on the head side, from the last step
    /// Servo speed commands, rad/s, one per joint; each motor is limited to its servo's torque.
    void set_motor_velocities(const double* commands);
    void step(double dt);

    BodyState body(int body) const;
    /// Centre of mass of a body, m (cheaper than body()).
    Vec3 position(int body) const;
    /// Speed of a body's centre of mass, m/s.
    double speed(int body) const;
    JointError joint_error(int joint) const;
    int contact_count() const;

    /// The Bullet world and bodies, for the other Bullet code of this folder (sensor_probes).
    btDiscreteDynamicsWorld& bullet_world() const;
    btRigidBody& bullet_body(int body) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace gaitlab
