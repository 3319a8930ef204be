// Hindmarsh-Rose bursting neurons, one per joint, with inhibitory synapses between neighbours
// (after Herrero-Carron, Rodriguez and Varona). In model time s = time_scale * t:
//   dx/ds = y + 3 x^2 - x^3 - z + current + synaptic input
//   dy/ds = 1 - 5 x^2 - y
//   dz/ds = slow_rate (4 (x + 1.6) - z)
// A joint bends to +amplitude while its neuron bursts and to -amplitude while it rests,
// smoothed by a first-order filter: angle_m = amplitude (2 b_m - 1) + offset   [deg].
#pragma once

#include <memory>
#include <vector>

#include "gaitlab/controller.h"

namespace gaitlab::controllers {

namespace detail {
class Rk4;
}

class HindmarshRose final : public Controller {
  public:
    HindmarshRose();
    /// A copy with this one's whole state (clone()).
    HindmarshRose(const HindmarshRose& other);
    ~HindmarshRose() override;
    void step(ControlIO& io) override;
    std::unique_ptr<Controller> clone() const override;

    /// Parameter indices, in declaration order.
    enum Param {
        amplitude,
        offset,
        current,
        slow_rate,
        time_scale,
        synapse,
        burst_gap,
        smoothing,
        seed
    };
    /// Value indices: membrane x, slow z, 1 while bursting, spikes in the last complete burst,
    /// output angle (deg).
    enum Value { x, z, bursting, burst_spikes, angle };

  protected:
    void on_bind() override;

  private:
    /// x, y, z of joint 0, then of joint 1, ...
    std::vector<double> state_;
    std::vector<double> since_spike_;  ///< model time since each neuron's last spike
    std::vector<int> count_;           ///< spikes so far in each neuron's burst
    std::vector<double> level_;        ///< b, the smoothed burst indicator
    std::vector<double> sigmoid_;      ///< scratch: each neuron's presynaptic sigmoid
    std::unique_ptr<detail::Rk4> rk4_;
};

}  // namespace gaitlab::controllers
