// The sine generator (Gonzalez-Gomez): joint m of its group (0-based from the tail) follows
//   angle_m(t) = amplitude * sin(2 pi frequency t + m * phase + phase0) + offset   [deg]
#pragma once

#include <memory>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

class Sine final : public Controller {
  public:
    Sine();
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param { amplitude, frequency, phase, phase0, offset };
    /// Value indices: per-joint time (s) and angle (deg).
    enum Value { time, angle };
};

}  // namespace gaitlab::controllers
