// A constant angle per joint. Combined with a sine by overlapping groups it bends the body:
// a yaw offset turns a pitch-yaw robot.
#pragma once

#include <memory>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

class Offset final : public Controller {
  public:
    Offset();
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices.
    enum Param { angle };
};

}  // namespace gaitlab::controllers
