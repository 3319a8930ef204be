// The baseline of the overhead benchmark: the benchmark snake written directly against Bullet,
// with no gaitlab code but the engine's constraint solver (engine/src/bullet/coulomb_solver.h,
// the contact model, header-only). It builds the same bodies, hinges, floor and solver settings
// as the engine, applies the same servo law every tick and the same sine gait every control_every
// ticks, so it steps the same trajectory; the difference in run time is what gaitlab adds.
#pragma once

#include <memory>

#include "scenario.h"

struct btContactSolverInfo;

namespace gaitlab_bench {

struct Vec {
    double x = 0, y = 0, z = 0;
};

/// What the raw loop may do otherwise than the engine (solver_knobs measures each).
struct RawOptions {
    /// box-floor contact points: the engine's (its box-plane collider, every touching corner:
    /// engine/src/bullet/box_plane.h), Bullet's convex-plane path with its multipoint search
    /// (the engine's before it), or 4 corners only for a face lying flat and else the deepest 2
    enum class Contacts { engine, bullet_multipoint, box_plane_fewer };
    Contacts contacts = Contacts::engine;
    /// > 0: the joints' rows are solved in this many iterations (Bullet's per-constraint
    /// override), the contacts' in the solver's own count
    int joint_iterations = 0;
};

class RawSnake {
  public:
    explicit RawSnake(const Scenario& scenario, const RawOptions& options = {});
    ~RawSnake();
    RawSnake(const RawSnake&) = delete;
    RawSnake& operator=(const RawSnake&) = delete;

    /// The hot loop: read joints, gait (when due), servo law, one Bullet step; `ticks` times.
    void step(long ticks);
    long ticks() const;

    /// Centre of mass minus its value at the start, m.
    Vec displacement() const;
    /// Largest pivot separation (m) and axis misalignment (rad) over the joints, right now.
    double max_separation() const;
    double max_axis_angle() const;
    int contact_count() const;
    /// The Bullet world's solver settings, to try other ones than the engine's (solver_knobs).
    btContactSolverInfo& solver_info();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace gaitlab_bench
