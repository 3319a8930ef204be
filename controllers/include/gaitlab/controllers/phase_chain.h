// Amplitude-controlled phase oscillators in a chain (Ijspeert et al. 2007; Crespi & Ijspeert,
// AmphiBot): one oscillator per joint, coupled to its neighbours so that, once locked, joint m
// leads joint m - 1 by `phase`, like the sine generator:
//   dtheta_m/dt = 2 pi frequency + sum_{j = m +- 1} coupling r_j sin(theta_j - theta_m - phi_mj)
//   d2r_m/dt2   = gain (gain / 4 (amplitude - r_m) - dr_m/dt)
//   angle_m     = r_m sin(theta_m) + offset                              [deg]
// with phi_{m,m-1} = -phase and phi_{m,m+1} = +phase.
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

namespace detail {
class Rk4;
}

class PhaseChain final : public Controller {
  public:
    PhaseChain();
    /// A copy with this one's whole state (clone()).
    PhaseChain(const PhaseChain& other);
    ~PhaseChain() override;
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param { amplitude, frequency, phase, offset, coupling, gain, seed };
    /// Value indices: per-joint phase theta (deg, in [0, 360)), amplitude r (deg) and output
    /// angle (deg).
    enum Value { theta, radius, angle };

  protected:
    void on_bind() override;

  private:
    void publish();

    /// theta (rad) of every joint, then r (rad), then dr/dt (rad/s).
    std::vector<double> state_;
    std::unique_ptr<detail::Rk4> rk4_;
};

}  // namespace gaitlab::controllers
