// PGPE as in F. Sehnke, C. Osendorfer, T. Rückstieß, A. Graves, J. Peters, J. Schmidhuber,
// "Parameter-exploring policy gradients", Neural Networks 23(4), 2010: symmetric sampling
// (their algorithm 2), a moving-average baseline and reward normalisation by the best reward
// seen. Each generation is population / 2 pairs mean +- epsilon, epsilon ~ N(0, diag(sigma^2)),
// in the normalised space; the gradient terms are averaged over the pairs.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "gaitlab/error.h"
#include "method_base.h"

namespace gaitlab::optimize {
namespace detail {
namespace {

// the smallest deviation, in range widths: sigma may shrink to it but not to 0
constexpr double kMinSigma = 1e-12;

class Pgpe : public MethodBase {
  public:
    Pgpe(std::vector<Parameter> parameters, const PgpeOptions& o, std::uint64_t seed)
        : MethodBase("pgpe", std::move(parameters), seed), o_(o) {
        if (o_.population < 2 || o_.population % 2 != 0)
            throw Error(
                fmt::format("pgpe: population {} must be even and at least 2 (symmetric "
                            "pairs mean +- epsilon)",
                            o_.population));
        if (!(o_.learning_rate_mean > 0 && std::isfinite(o_.learning_rate_mean)))
            throw Error(fmt::format("pgpe: learning_rate_mean {} must be a positive number",
                                    o_.learning_rate_mean));
        if (!(o_.learning_rate_sigma >= 0 && std::isfinite(o_.learning_rate_sigma)))
            throw Error(fmt::format("pgpe: learning_rate_sigma {} must be a number >= 0",
                                    o_.learning_rate_sigma));
        if (!(o_.sigma > 0 && o_.sigma <= 1))
            throw Error(fmt::format("pgpe: sigma {} must be in (0, 1] (range widths)", o_.sigma));
        if (!(o_.baseline_decay >= 0 && o_.baseline_decay < 1))
            throw Error(
                fmt::format("pgpe: baseline_decay {} must be in [0, 1)", o_.baseline_decay));
        mean_ = initial_point(this->parameters(), o_.initial, "pgpe");
        sigma_.assign(dimensions(), o_.sigma);
    }

  protected:
    Points sample() override {
        const std::size_t n = dimensions();
        Points out;
        epsilon_.clear();
        for (int k = 0; k < o_.population / 2; ++k) {
            Vector e(n), plus(n), minus(n);
            for (std::size_t i = 0; i < n; ++i) {
                e[i] = sigma_[i] * random_.normal();
                plus[i] = mean_[i] + e[i];
                minus[i] = mean_[i] - e[i];
            }
            epsilon_.push_back(std::move(e));
            out.push_back(std::move(plus));
            out.push_back(std::move(minus));
        }
        return out;
    }

    void update(const Points&, const Vector& fitness) override {
        const std::size_t n = dimensions();
        const std::size_t pairs = fitness.size() / 2;
        // failures count as this generation's worst reward (ranked last); a generation without
        // any success changes nothing
        double worst = 0;
        bool any = false;
        for (double f : fitness)
            if (!std::isnan(f)) {
                worst = any ? std::min(worst, f) : f;
                any = true;
            }
        if (!any) return;
        Vector r(fitness);
        for (double& v : r)
            if (std::isnan(v)) v = worst;

        double total = 0;
        for (double v : r) {
            total += v;
            if (!has_best_ || v > best_reward_) best_reward_ = v;
            has_best_ = true;
        }
        const double average = total / static_cast<double>(r.size());
        if (!has_baseline_) {
            baseline_ = average;
            has_baseline_ = true;
        }

        Vector step_mean(n, 0.0), step_sigma(n, 0.0);
        for (std::size_t k = 0; k < pairs; ++k) {
            const double plus = r[2 * k], minus = r[2 * k + 1];
            // the mean follows the pair's difference, normalised by how far both are from the
            // best reward seen; sigma follows the pair's average against the baseline
            const double t_denominator = 2 * best_reward_ - plus - minus;
            const double r_t = t_denominator > 0 ? (plus - minus) / t_denominator : 0.0;
            const double s_denominator = best_reward_ - baseline_;
            const double r_s =
                s_denominator > 0
                    ? std::clamp(((plus + minus) / 2 - baseline_) / s_denominator, -1.0, 1.0)
                    : 0.0;
            for (std::size_t i = 0; i < n; ++i) {
                const double e = epsilon_[k][i];
                step_mean[i] += e * r_t;
                step_sigma[i] += (e * e - sigma_[i] * sigma_[i]) / sigma_[i] * r_s;
            }
        }
        const double count = static_cast<double>(pairs);
        for (std::size_t i = 0; i < n; ++i) {
            mean_[i] =
                std::clamp(mean_[i] + o_.learning_rate_mean * step_mean[i] / count, 0.0, 1.0);
            sigma_[i] = std::clamp(sigma_[i] + o_.learning_rate_sigma * step_sigma[i] / count,
                                   kMinSigma, 1.0);
        }
        baseline_ = o_.baseline_decay * baseline_ + (1 - o_.baseline_decay) * average;
    }

    Json options_json() const override {
        return {{"population", o_.population},
                {"learning_rate_mean", o_.learning_rate_mean},
                {"learning_rate_sigma", o_.learning_rate_sigma},
                {"sigma", o_.sigma},
                {"baseline_decay", o_.baseline_decay},
                {"initial", vector_json(o_.initial)}};
    }
    Json state_json() const override {
        return {{"mean", vector_json(mean_)},
                {"sigma", vector_json(sigma_)},
                {"epsilon", points_json(epsilon_)},
                {"baseline", has_baseline_ ? Json(baseline_) : Json(nullptr)},
                {"best_reward", has_best_ ? Json(best_reward_) : Json(nullptr)}};
    }
    void load_state(const Json& s) override {
        const std::size_t n = dimensions();
        mean_ = read_vector(s, "mean", n);
        sigma_ = read_vector(s, "sigma", n);
        for (double v : mean_)
            if (!(v >= 0 && v <= 1)) throw Error("'mean': expected numbers in [0, 1]");
        for (double v : sigma_)
            if (!(v >= kMinSigma && v <= 1)) throw Error("'sigma': expected numbers in (0, 1]");
        epsilon_ = read_points(s, "epsilon", n);
        for (const Vector& e : epsilon_)
            for (double v : e)
                if (!std::isfinite(v)) throw Error("'epsilon': expected finite numbers");
        baseline_ = read_number(s, "baseline");
        has_baseline_ = !std::isnan(baseline_);
        best_reward_ = read_number(s, "best_reward");
        has_best_ = !std::isnan(best_reward_);
    }

  private:
    PgpeOptions o_;
    Vector mean_, sigma_;
    Points epsilon_;  // the pending generation's perturbations, one per pair
    double baseline_ = 0, best_reward_ = 0;
    bool has_baseline_ = false, has_best_ = false;
};

}  // namespace

std::unique_ptr<MethodBase> make_saved_pgpe(std::vector<Parameter> p, const Json& j,
                                            std::uint64_t seed) {
    PgpeOptions o;
    o.population = static_cast<int>(read_integer(j, "population", 0, INT32_MAX));
    o.learning_rate_mean = read_finite(j, "learning_rate_mean");
    o.learning_rate_sigma = read_finite(j, "learning_rate_sigma");
    o.sigma = read_finite(j, "sigma");
    o.baseline_decay = read_finite(j, "baseline_decay");
    const Json& initial = j.at("initial");
    o.initial =
        initial.is_array() && initial.empty() ? Vector{} : read_vector(j, "initial", p.size());
    return std::make_unique<Pgpe>(std::move(p), o, seed);
}

}  // namespace detail

std::unique_ptr<Method> make_pgpe(std::vector<Parameter> parameters, const PgpeOptions& options,
                                  std::uint64_t seed) {
    return std::make_unique<detail::Pgpe>(std::move(parameters), options, seed);
}

}  // namespace gaitlab::optimize
