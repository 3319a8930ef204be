// What the controller tests share: a rig that drives one controller alone, without physics,
// its joints still at zero, and angle helpers.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::test {

constexpr double kTestPi = 3.14159265358979323846;

// joints that never move
class StillJoints final : public JointReader {
  public:
    double angle(int) const override { return 0; }
    double velocity(int) const override { return 0; }
    double torque(int) const override { return 0; }
};

// drives a controller bound to n joints (indices 0..n-1) in control steps of dt seconds
struct Rig {
    Rig(Controller& c, int n) : ctl(c), joints(static_cast<size_t>(n)), targets(joints.size()) {
        for (int m = 0; m < n; ++m)
            joints[static_cast<size_t>(m)] = m;
        ctl.bind(n);
    }
    void run(double seconds, double dt = 0.03) {
        run_each(seconds, dt, [](double) {});
    }
    // runs `seconds`, calling each(t) after every step, t the time the step started at
    template <class Each>
    void run_each(double seconds, double dt, Each&& each) {
        const long steps = std::lround(seconds / dt);
        for (long k = 0; k < steps; ++k) {
            ControlIO io(dt, time, joints, reader, targets.data());
            ctl.step(io);
            each(time);
            time += dt;
        }
    }
    Controller& ctl;
    std::vector<int> joints;
    std::vector<double> targets;
    StillJoints reader;
    double time = 0;
};

// a - b wrapped into (-180, 180], degrees
inline double angle_diff_deg(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d <= -180) d += 360;
    if (d > 180) d -= 360;
    return d;
}

}  // namespace gaitlab::test
