// Distributed control in the style of Conradt & Varshavskaya's WormBot: every module runs its
// own phase oscillator, on its own clock, and hears only its neighbours' phases, exchanged once
// per control step:
//   dtheta_m/dt = 2 pi f_m + coupling sum_{j = m +- 1} sin(psi_j - theta_m - phi_mj)
//   angle_m     = amplitude sin(theta_m) + offset                             [deg]
// psi_j is the phase j last sent, advanced at the nominal frequency; phi_{m,m-1} = -phase,
// phi_{m,m+1} = +phase. A failed module stops and relays messages between its neighbours.
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

namespace detail {
class Rk4;
}

class Distributed final : public Controller {
  public:
    Distributed();
    /// A copy with this one's whole state (clone()).
    Distributed(const Distributed& other);
    ~Distributed() override;
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param { amplitude, frequency, phase, offset, coupling, detuning, failed, seed };
    /// Value indices: per-joint phase theta (deg, in [0, 360)), own frequency (Hz) and output
    /// angle (deg).
    enum Value { theta, own_frequency, angle };

  protected:
    void on_bind() override;

  private:
    void update_clocks();
    void publish();

    /// theta (rad) of every module, then the phases its neighbours believe it has (rad).
    std::vector<double> state_;
    std::unique_ptr<detail::Rk4> rk4_;
};

}  // namespace gaitlab::controllers
