// A constant angle per joint. Combined with a sine by overlapping groups it bends the body:
// a yaw offset turns a pitch-yaw robot.
#pragma once

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

class Offset final : public Controller {
  public:
    Offset();
    void step(ControlIO& io) override;

    /// Parameter indices.
    enum Param { angle };
};

}  // namespace gaitlab::controllers
