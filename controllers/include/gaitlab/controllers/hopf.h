// A chain of Hopf oscillators (Righetti & Ijspeert; Buchli), one per joint, with diffusive
// coupling through rotation matrices so that, once locked, joint m leads joint m - 1 by `phase`:
//   dz_m/dt = (convergence (1 - |z_m|^2) + i 2 pi frequency) z_m
//             + coupling sum_{j = m +- 1} (R(phi_mj) z_j - z_m),      z = x + i y
//   angle_m = amplitude * y_m + offset                                   [deg]
// with phi_{m,m-1} = +phase and phi_{m,m+1} = -phase; the limit cycle has radius 1 (mu = 1).
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

namespace detail {
class Rk4;
}

class Hopf final : public Controller {
  public:
    Hopf();
    /// A copy with this one's whole state (clone()).
    Hopf(const Hopf& other);
    ~Hopf() override;
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param { amplitude, frequency, phase, offset, convergence, coupling, seed };
    /// Value indices: per-joint state x and y (dimensionless) and output angle (deg).
    enum Value { x, y, angle };

  protected:
    void on_bind() override;

  private:
    void publish();

    /// x of every joint, then y.
    std::vector<double> state_;
    std::unique_ptr<detail::Rk4> rk4_;
};

}  // namespace gaitlab::controllers
