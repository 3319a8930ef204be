// The real-valued genetic algorithm: tournament selection, simulated binary crossover and
// polynomial mutation (Deb and Agrawal 1995; Deb and Goyal 1996) in the normalised space [0, 1]^n,
// children clamped into it, and elitism.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "gaitlab/error.h"
#include "method_base.h"

namespace gaitlab::optimize {
namespace detail {
namespace {

class Ga : public MethodBase {
  public:
    Ga(std::vector<Parameter> parameters, const GaOptions& o, std::uint64_t seed)
        : MethodBase("ga", std::move(parameters), seed), o_(o) {
        const int n = static_cast<int>(dimensions());
        if (o_.population < 4)
            throw Error(
                fmt::format("ga: population {} is too small (expected at least 4)", o_.population));
        if (o_.elites < 0 || o_.elites > o_.population - 2)
            throw Error(fmt::format("ga: elites {} must be in [0, population - 2 = {}]", o_.elites,
                                    o_.population - 2));
        if (o_.tournament < 2 || o_.tournament > o_.population)
            throw Error(fmt::format("ga: tournament {} must be in [2, population = {}]",
                                    o_.tournament, o_.population));
        if (!(o_.crossover_rate >= 0 && o_.crossover_rate <= 1))
            throw Error(fmt::format("ga: crossover_rate {} must be in [0, 1]", o_.crossover_rate));
        if (!(o_.crossover_eta > 0 && std::isfinite(o_.crossover_eta)))
            throw Error(
                fmt::format("ga: crossover_eta {} must be a positive number", o_.crossover_eta));
        if (!(o_.mutation_eta > 0 && std::isfinite(o_.mutation_eta)))
            throw Error(
                fmt::format("ga: mutation_eta {} must be a positive number", o_.mutation_eta));
        if (std::isnan(o_.mutation_rate) || o_.mutation_rate > 1)
            throw Error(
                fmt::format("ga: mutation_rate {} must be in [0, 1] (or negative: "
                            "1 / dimensions)",
                            o_.mutation_rate));
        if (o_.mutation_rate < 0) o_.mutation_rate = 1.0 / n;
        initial_ =
            o_.initial.empty() ? Vector{} : initial_point(this->parameters(), o_.initial, "ga");
    }

  protected:
    Points sample() override {
        const std::size_t n = dimensions();
        Points children;
        if (population_.empty()) {
            for (int i = 0; i < o_.population; ++i) {
                Vector u(n);
                for (double& v : u)
                    v = random_.uniform();
                children.push_back(std::move(u));
            }
            if (!initial_.empty()) children[0] = initial_;
            return children;
        }
        const std::size_t wanted = static_cast<std::size_t>(o_.population - o_.elites);
        while (children.size() < wanted) {
            Vector a = population_[tournament()];
            Vector b = population_[tournament()];
            if (random_.uniform() < o_.crossover_rate) crossover(a, b);
            mutate(a);
            mutate(b);
            children.push_back(std::move(a));
            if (children.size() < wanted) children.push_back(std::move(b));
        }
        return children;
    }

    void update(const Points& u, const Vector& fitness) override {
        Points pool;
        Vector pool_fitness;
        // the elites of the last generation (first after the initial one) compete with the
        // children: the next population is the elites and the children
        if (!population_.empty()) {
            const auto order = ranking(fitness_);
            for (int e = 0; e < o_.elites; ++e) {
                pool.push_back(population_[order[static_cast<std::size_t>(e)]]);
                pool_fitness.push_back(fitness_[order[static_cast<std::size_t>(e)]]);
            }
        }
        pool.insert(pool.end(), u.begin(), u.end());
        pool_fitness.insert(pool_fitness.end(), fitness.begin(), fitness.end());
        population_ = std::move(pool);
        fitness_ = std::move(pool_fitness);
    }

    Json options_json() const override {
        return {{"population", o_.population},       {"elites", o_.elites},
                {"tournament", o_.tournament},       {"crossover_rate", o_.crossover_rate},
                {"crossover_eta", o_.crossover_eta}, {"mutation_rate", o_.mutation_rate},
                {"mutation_eta", o_.mutation_eta},   {"initial", vector_json(o_.initial)}};
    }
    Json state_json() const override {
        return {{"population", points_json(population_)}, {"fitness", vector_json(fitness_)}};
    }
    void load_state(const Json& state) override {
        population_ = read_points(state, "population", dimensions());
        fitness_ = read_vector(state, "fitness", population_.size());
        if (!population_.empty() && population_.size() != static_cast<std::size_t>(o_.population))
            throw Error(fmt::format("'population': expected {} individuals", o_.population));
        for (const Vector& u : population_)
            for (double v : u)
                if (!(v >= 0 && v <= 1)) throw Error("'population': expected numbers in [0, 1]");
    }

  private:
    // the best of `tournament` individuals drawn with replacement (failures lose)
    std::size_t tournament() {
        std::size_t best = random_.below(population_.size());
        for (int k = 1; k < o_.tournament; ++k) {
            const std::size_t c = random_.below(population_.size());
            if (std::isnan(fitness_[best]) || fitness_[c] > fitness_[best]) best = c;
        }
        return best;
    }

    // SBX: each gene is crossed with probability 1/2, the spread factor beta drawn so that
    // children lie around the parents as a one-point crossover of binary strings would put them
    void crossover(Vector& a, Vector& b) {
        const double e = 1.0 / (o_.crossover_eta + 1.0);
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (random_.uniform() >= 0.5) continue;
            const double r = random_.uniform();
            const double beta =
                r <= 0.5 ? std::pow(2.0 * r, e) : std::pow(1.0 / (2.0 * (1.0 - r)), e);
            const double x = a[i], y = b[i];
            a[i] = std::clamp(0.5 * ((1 + beta) * x + (1 - beta) * y), 0.0, 1.0);
            b[i] = std::clamp(0.5 * ((1 - beta) * x + (1 + beta) * y), 0.0, 1.0);
        }
    }

    // polynomial mutation: a step in (-1, 1) range widths, small steps far likelier than large
    void mutate(Vector& a) {
        const double e = 1.0 / (o_.mutation_eta + 1.0);
        for (double& x : a) {
            if (random_.uniform() >= o_.mutation_rate) continue;
            const double r = random_.uniform();
            const double delta =
                r < 0.5 ? std::pow(2.0 * r, e) - 1.0 : 1.0 - std::pow(2.0 * (1.0 - r), e);
            x = std::clamp(x + delta, 0.0, 1.0);
        }
    }

    GaOptions o_;
    Vector initial_;
    Points population_;  // the last generation's individuals, elites first, and their fitness
    Vector fitness_;
};

}  // namespace

std::unique_ptr<MethodBase> make_saved_ga(std::vector<Parameter> p, const Json& j,
                                          std::uint64_t seed) {
    GaOptions o;
    o.population = static_cast<int>(read_integer(j, "population", 0, INT32_MAX));
    o.elites = static_cast<int>(read_integer(j, "elites", 0, INT32_MAX));
    o.tournament = static_cast<int>(read_integer(j, "tournament", 0, INT32_MAX));
    o.crossover_rate = read_finite(j, "crossover_rate");
    o.crossover_eta = read_finite(j, "crossover_eta");
    o.mutation_rate = read_finite(j, "mutation_rate");
    o.mutation_eta = read_finite(j, "mutation_eta");
    const Json& initial = j.at("initial");
    o.initial =
        initial.is_array() && initial.empty() ? Vector{} : read_vector(j, "initial", p.size());
    return std::make_unique<Ga>(std::move(p), o, seed);
}

}  // namespace detail

std::unique_ptr<Method> make_ga(std::vector<Parameter> parameters, const GaOptions& options,
                                std::uint64_t seed) {
    return std::make_unique<detail::Ga>(std::move(parameters), options, seed);
}

}  // namespace gaitlab::optimize
