// The Bullet side of a simulation. Only this folder includes Bullet headers; this interface
// speaks gaitlab types. Bodies are numbered robot by robot (in WorldSpec order) and then the
// dynamic objects (in world_solids order); joints robot by robot.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <vector>

#include "gaitlab/options.h"
#include "gaitlab/types.h"
#include "gaitlab/world.h"

class btDiscreteDynamicsWorld;
class btRigidBody;

namespace gaitlab {

/// "3.24": the version of the Bullet library this engine was built with.
const char* physics_version();

class PhysicsWorld {
  public:
    /// Builds the Bullet scene for `world`; `dt` sets the servo torque limits as impulses.
    /// `newton_steps` Newton steps follow block_nncg's iterations (SimulationOptions; none with
    /// pgs). Throws SpecError if a heightfield's image cannot be read.
    PhysicsWorld(const WorldSpec& world, double dt, int solver_iterations,
                 ConstraintSolver solver = ConstraintSolver::pgs, int newton_steps = 0);
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

    /// A body's state: the pose of its shape (its centre and axes, as BodySpec::pose and every
    /// reader of poses take it), the velocity of its shape's centre, its angular velocity.
    BodyState body(int body) const;
    /// Centre of mass of a body, m (cheaper than body()); its shape's centre unless the body
    /// has a centre of mass of its own (BodySpec::center_of_mass).
    Vec3 position(int body) const;
    /// Centre of a body's shape, m: body().pose.position, cheaper.
    Vec3 shape_position(int body) const;
    /// Velocity of a body's centre of mass, m/s.
    Vec3 mass_velocity(int body) const;
    /// Speed of a body's centre of mass, m/s.
    double speed(int body) const;
    /// A body's centre of mass in its shape's frame, m (zero unless it has one of its own). Bullet
    /// places the body's frame there: its contact points' local coordinates are from it.
    Vec3 center_of_mass(int body) const;
    JointError joint_error(int joint) const;
    /// The first body (robots' bodies, then dynamic objects, as numbered above) whose state
    /// is not finite (position, orientation, velocities), lies farther than `max_distance` m
    /// from the origin or moves faster than `max_speed` m/s; -1 if none. Cheap: a few dozen
    /// instructions per body, run after every step.
    int first_diverged(double max_distance, double max_speed) const;

    /// Where a robot body and something else (the floor, an object, another robot's body)
    /// interpenetrate.
    struct Overlap {
        int body = -1;        ///< the robot body (numbered as above)
        std::string other;    ///< "the floor", "wall 1", "rubble 2", "robot 3 body 5" ...
        int other_body = -1;  ///< the other body's number if it is a robot body or dynamic object
        double depth = 0;     ///< m, > 0
    };
    /// The deepest overlap of any robot body deeper than `tolerance` m in the state as it
    /// stands (before any step), if any. Does not change the world (a contact test, not a
    /// collision pass).
    std::optional<Overlap> deepest_robot_overlap(double tolerance) const;
    /// Whether a robot's bodies may pass through each other: one of its bodies does not
    /// collide with another (self_collision off) though no joint joins them and they did not
    /// overlap as built.
    bool may_pass_through_itself() const;
    /// The deepest penetration, deeper than `tolerance` m, of two such bodies of one robot in
    /// the state as it stands (`body` < `other_body`); none if the robot's bodies keep apart.
    /// Does not change the world (contact tests of the pairs whose bounding boxes overlap).
    std::optional<Overlap> deepest_self_pass(double tolerance) const;
    int contact_count() const;
    /// The contact points closer than 1 mm after the last step, their force the impulse over
    /// `dt`, into `out` (cleared first).
    void contacts(std::vector<ContactPoint>& out, double dt) const;

    /// Makes this world, built from the same spec as `from`, continue as `from` would: every
    /// body's state (pose, velocities and what Bullet interpolates), the joints' motor
    /// commands and measured reactions, the broadphase's pairs in `from`'s order, and the
    /// contact manifolds (points, their warm-start impulses and lifetimes) in `from`'s order.
    /// Two worlds built from one spec and given the same `from` are identical in every part of
    /// their state, so their futures are bit-identical (Simulation::clone). Throws Error if
    /// the worlds do not have the same bodies and joints. `impulse_scale` multiplies the
    /// impulses the next solve starts from (contacts' and joints'): this world's dt over
    /// `from`'s, for a world stepping at another dt (the same forces); 1 leaves their bits.
    void copy_state_from(const PhysicsWorld& from, double impulse_scale = 1);

    /// The Bullet world and bodies, for the other Bullet code of this folder (sensor_probes).
    btDiscreteDynamicsWorld& bullet_world() const;
    btRigidBody& bullet_body(int body) const;

  private:
    void find_self_pairs(const WorldSpec& spec);

    struct Impl;
    std::unique_ptr<Impl> impl_;
    int first_object_body_ = 0;  // robots' bodies come before it
};

}  // namespace gaitlab
