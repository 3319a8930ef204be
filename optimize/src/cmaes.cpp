// CMA-ES as in N. Hansen, "The CMA Evolution Strategy: A Tutorial" (arXiv:1604.00772), with its
// default strategy parameters: (mu/mu_w, lambda) selection with positive recombination weights,
// cumulative step-size adaptation, rank-one and rank-mu covariance updates, and the
// repair-and-penalise handling of bounds of its appendix B. The search runs in the normalised
// space, where every parameter's range is [0, 1].
#include <fmt/format.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "gaitlab/error.h"
#include "method_base.h"

namespace gaitlab::optimize {
namespace detail {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

VectorXd to_eigen(const Vector& v) {
    return Eigen::Map<const VectorXd>(v.data(), v.size());
}
Vector from_eigen(const VectorXd& v) {
    return Vector(v.data(), v.data() + v.size());
}

Json matrix_json(const MatrixXd& m) {
    Json j = Json::array();
    for (Eigen::Index r = 0; r < m.rows(); ++r)
        j.push_back(vector_json(from_eigen(m.row(r))));
    return j;
}

MatrixXd read_matrix(const Json& j, const char* key, std::size_t n) {
    const Points rows = read_points(j, key, n);
    if (rows.size() != n) throw Error(fmt::format("'{}': expected {} rows", key, n));
    MatrixXd m(n, n);
    for (std::size_t r = 0; r < n; ++r)
        for (std::size_t c = 0; c < n; ++c) {
            if (!std::isfinite(rows[r][c]))
                throw Error(fmt::format("'{}': expected finite numbers", key));
            m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
        }
    return m;
}

class Cmaes : public MethodBase {
  public:
    Cmaes(std::vector<Parameter> parameters, const CmaesOptions& o, std::uint64_t seed)
        : MethodBase("cmaes", std::move(parameters), seed), o_(o) {
        const auto n = static_cast<double>(dimensions());
        if (o_.population == 0) o_.population = 4 + static_cast<int>(std::floor(3.0 * std::log(n)));
        if (o_.population < 4)
            throw Error(
                fmt::format("cmaes: population {} is too small (expected at least 4, or 0 "
                            "for the default)",
                            o_.population));
        if (!(o_.sigma > 0 && o_.sigma <= 1))
            throw Error(fmt::format("cmaes: sigma {} must be in (0, 1] (range widths)", o_.sigma));
        const Vector start = initial_point(this->parameters(), o_.initial, "cmaes");

        // selection and recombination: weights w_i = ln((lambda + 1) / 2) - ln i, i = 1..mu
        const int lambda = o_.population;
        mu_ = lambda / 2;
        weights_.resize(mu_);
        for (int i = 0; i < mu_; ++i)
            weights_[i] = std::log((lambda + 1) / 2.0) - std::log(static_cast<double>(i + 1));
        weights_ /= weights_.sum();
        mu_eff_ = 1.0 / weights_.squaredNorm();
        // step-size control
        c_sigma_ = (mu_eff_ + 2) / (n + mu_eff_ + 5);
        d_sigma_ = 1 + 2 * std::max(0.0, std::sqrt((mu_eff_ - 1) / (n + 1)) - 1) + c_sigma_;
        // covariance adaptation
        c_c_ = (4 + mu_eff_ / n) / (n + 4 + 2 * mu_eff_ / n);
        c_1_ = 2 / ((n + 1.3) * (n + 1.3) + mu_eff_);
        c_mu_ = std::min(1 - c_1_, 2 * (mu_eff_ - 2 + 1 / mu_eff_) / ((n + 2) * (n + 2) + mu_eff_));
        chi_n_ = std::sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n));

        mean_ = to_eigen(start);
        sigma_ = o_.sigma;
        const auto d = static_cast<Eigen::Index>(dimensions());
        c_ = MatrixXd::Identity(d, d);
        b_ = MatrixXd::Identity(d, d);
        d_ = VectorXd::Ones(d);
        p_c_ = VectorXd::Zero(d);
        p_sigma_ = VectorXd::Zero(d);
    }

  protected:
    Points sample() override {
        const auto d = static_cast<Eigen::Index>(dimensions());
        Points out;
        for (int k = 0; k < o_.population; ++k) {
            VectorXd z(d);
            for (Eigen::Index i = 0; i < d; ++i)
                z(i) = random_.normal();
            const VectorXd x = mean_ + sigma_ * (b_ * d_.cwiseProduct(z));
            out.push_back(from_eigen(x));
        }
        return out;
    }

    void update(const Points& u, const Vector& fitness) override {
        const auto d = static_cast<Eigen::Index>(dimensions());
        const auto n = static_cast<double>(dimensions());
        // ranking key: the fitness of the clamped point, less a penalty for the squared distance
        // outside [0, 1], scaled by this generation's spread of fitness (so its weight does not
        // depend on the fitness's unit)
        double lo = 0, hi = 0;
        bool any = false;
        for (double f : fitness)
            if (!std::isnan(f)) {
                lo = any ? std::min(lo, f) : f;
                hi = any ? std::max(hi, f) : f;
                any = true;
            }
        const double spread = hi > lo ? hi - lo : 1.0;
        Vector key(fitness);
        for (std::size_t k = 0; k < u.size(); ++k) {
            double outside = 0;
            for (double v : u[k]) {
                const double e = v - std::clamp(v, 0.0, 1.0);
                outside += e * e;
            }
            key[k] -= spread * outside;
        }
        const auto order = ranking(key);

        // the mu best that did not fail are selected; when failures leave fewer, their weights
        // are renormalised, and a generation without any success changes nothing
        int selected = 0;
        while (selected < mu_ && !std::isnan(key[order[static_cast<std::size_t>(selected)]]))
            ++selected;
        if (selected == 0) return;
        const VectorXd w = weights_.head(selected) / weights_.head(selected).sum();
        const double mu_eff = 1.0 / w.squaredNorm();

        // recombination: the new mean moves along the weighted mean step y_w
        VectorXd y_w = VectorXd::Zero(d);
        MatrixXd rank_mu = MatrixXd::Zero(d, d);
        for (int i = 0; i < selected; ++i) {
            const VectorXd y = (to_eigen(u[order[static_cast<std::size_t>(i)]]) - mean_) / sigma_;
            y_w += w[i] * y;
            rank_mu += w[i] * y * y.transpose();
        }
        mean_ += sigma_ * y_w;

        // step-size control: the evolution path in the isotropic frame, C^-1/2 y_w
        const VectorXd c_inv_sqrt_y = b_ * (b_.transpose() * y_w).cwiseQuotient(d_);
        p_sigma_ = (1 - c_sigma_) * p_sigma_ +
                   std::sqrt(c_sigma_ * (2 - c_sigma_) * mu_eff) * c_inv_sqrt_y;
        const double generations = static_cast<double>(generation() + 1);
        const bool h_sigma =
            p_sigma_.norm() / std::sqrt(1 - std::pow(1 - c_sigma_, 2 * generations)) <
            (1.4 + 2 / (n + 1)) * chi_n_;
        p_c_ = (1 - c_c_) * p_c_ + (h_sigma ? std::sqrt(c_c_ * (2 - c_c_) * mu_eff) : 0.0) * y_w;
        const double delta_h = h_sigma ? 0.0 : c_c_ * (2 - c_c_);

        // covariance: rank-one (evolution path) and rank-mu (this generation's steps) updates
        c_ = (1 + c_1_ * delta_h - c_1_ - c_mu_) * c_ + c_1_ * p_c_ * p_c_.transpose() +
             c_mu_ * rank_mu;
        sigma_ *= std::exp(c_sigma_ / d_sigma_ * (p_sigma_.norm() / chi_n_ - 1));
        // a step larger than the whole space helps nothing and may overflow
        sigma_ = std::min(sigma_, 1e3);
        decompose();
    }

    Json options_json() const override {
        return {{"population", o_.population},
                {"sigma", o_.sigma},
                {"initial", vector_json(o_.initial)}};
    }
    Json state_json() const override {
        return {{"mean", vector_json(from_eigen(mean_))},
                {"sigma", sigma_},
                {"p_sigma", vector_json(from_eigen(p_sigma_))},
                {"p_c", vector_json(from_eigen(p_c_))},
                {"C", matrix_json(c_)},
                {"B", matrix_json(b_)},
                {"D", vector_json(from_eigen(d_))}};
    }
    void load_state(const Json& s) override {
        const std::size_t n = dimensions();
        auto finite = [&](const char* key) {
            const Vector v = read_vector(s, key, n);
            for (double x : v)
                if (!std::isfinite(x))
                    throw Error(fmt::format("'{}': expected finite numbers", key));
            return to_eigen(v);
        };
        mean_ = finite("mean");
        sigma_ = read_finite(s, "sigma");
        if (!(sigma_ > 0)) throw Error("'sigma': expected a positive number");
        p_sigma_ = finite("p_sigma");
        p_c_ = finite("p_c");
        c_ = read_matrix(s, "C", n);
        b_ = read_matrix(s, "B", n);
        d_ = finite("D");
        if (!(d_.minCoeff() > 0)) throw Error("'D': expected positive numbers");
    }

  private:
    // C = B diag(D^2) B^T; its symmetric part only (rounding makes it drift otherwise)
    void decompose() {
        c_ = 0.5 * (c_ + c_.transpose()).eval();
        Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(c_);
        if (eigen.info() != Eigen::Success) return;  // keep the last good decomposition
        const VectorXd values = eigen.eigenvalues();
        // eigenvalues that rounding made zero or negative: a tiny positive variance instead
        const double floor = std::max(values.maxCoeff(), 1e-300) * 1e-14;
        b_ = eigen.eigenvectors();
        d_ = values.cwiseMax(floor).cwiseSqrt();
    }

    CmaesOptions o_;
    int mu_ = 0;
    VectorXd weights_;
    double mu_eff_ = 0, c_sigma_ = 0, d_sigma_ = 0, c_c_ = 0, c_1_ = 0, c_mu_ = 0, chi_n_ = 0;
    VectorXd mean_;
    double sigma_ = 0;
    MatrixXd c_, b_;
    VectorXd d_, p_c_, p_sigma_;
};

}  // namespace

std::unique_ptr<MethodBase> make_saved_cmaes(std::vector<Parameter> p, const Json& j,
                                             std::uint64_t seed) {
    CmaesOptions o;
    o.population = static_cast<int>(read_integer(j, "population", 0, INT32_MAX));
    o.sigma = read_finite(j, "sigma");
    const Json& initial = j.at("initial");
    o.initial =
        initial.is_array() && initial.empty() ? Vector{} : read_vector(j, "initial", p.size());
    return std::make_unique<Cmaes>(std::move(p), o, seed);
}

}  // namespace detail

std::unique_ptr<Method> make_cmaes(std::vector<Parameter> parameters, const CmaesOptions& options,
                                   std::uint64_t seed) {
    return std::make_unique<detail::Cmaes>(std::move(parameters), options, seed);
}

}  // namespace gaitlab::optimize
