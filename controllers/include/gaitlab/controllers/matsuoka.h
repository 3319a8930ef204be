// Matsuoka half-centre oscillators (Matsuoka 1985; the CPG of M-TRAN): two mutually
// inhibiting neurons with adaptation per joint, neighbours coupled through weights:
//   tau du_i/dt = tonic - u_i - inhibition y_other - adaptation v_i + (neighbour input)
//   T dv_i/dt   = y_i - v_i,      y_i = max(0, u_i),     i = 1, 2
//   angle_m     = gain (y_1 - y_2) + offset                                  [deg]
// Phase lags are not commanded: they emerge from the `ascending` and `descending` weights.
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

namespace detail {
class Rk4;
}

class Matsuoka final : public Controller {
  public:
    Matsuoka();
    /// A copy with this one's whole state (clone()).
    Matsuoka(const Matsuoka& other);
    ~Matsuoka() override;
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param {
        gain,
        offset,
        rise_time,
        adaptation_time,
        inhibition,
        adaptation,
        tonic,
        ascending,
        descending,
        seed
    };
    /// Value indices: per-joint neuron states u1, u2 and output angle (deg).
    enum Value { u1, u2, angle };

  protected:
    void on_bind() override;

  private:
    void publish();

    /// u1, u2, v1, v2 of joint 0, then of joint 1, ...
    std::vector<double> state_;
    std::unique_ptr<detail::Rk4> rk4_;
};

}  // namespace gaitlab::controllers
