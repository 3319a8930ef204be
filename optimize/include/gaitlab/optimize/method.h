// The optimization methods as ask/tell over parameter vectors: ask() gives the individuals of a
// generation, the caller evaluates them however it likes (threads, MPI ranks) and tell() takes
// their fitness in ask order. Nothing here knows simulations, Lua or Bullet.
//
// Fitness is maximised (a speed, a distance). A NaN or infinite fitness marks a failed
// individual: it ranks below every other. A method's whole state, its random stream included,
// is a JSON text (save()), and load_method() makes a method that continues exactly where the
// saved one was: the same seed gives bit-identical generations, interrupted or not.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gaitlab/optimize/parameters.h"

namespace gaitlab::optimize {

/// An optimization method, one generation at a time.
class Method {
  public:
    virtual ~Method() = default;

    /// "ga", "cmaes" or "pgpe".
    virtual const std::string& name() const = 0;

    /// The parameters searched over, as given.
    virtual const std::vector<Parameter>& parameters() const = 0;

    /// The individuals of the current generation, in parameter units (inside the ranges,
    /// integers whole); the same ones until tell() is called. The reference lives until tell().
    virtual const std::vector<std::vector<double>>& ask() = 0;

    /// The fitness of each individual of ask(), in ask order (higher is better; NaN or infinite
    /// = failed, ranked last); ends the generation. Throws Error when ask() was not called or
    /// the number of values differs from the number of individuals.
    virtual void tell(const std::vector<double>& fitness) = 0;

    /// Generations completed (tell() calls).
    virtual int generation() const = 0;

    /// Individuals evaluated so far (sum of the sizes of the told generations).
    virtual std::int64_t evaluations() const = 0;

    /// The best individual told so far, in parameter units (empty before one with a finite
    /// fitness), and its fitness (NaN before then).
    virtual const std::vector<double>& best() const = 0;
    virtual double best_fitness() const = 0;

    /// The method's whole state as a JSON text (format "gaitlab-optimize-state", version 1).
    virtual std::string save() const = 0;
};

/// The real-valued genetic algorithm (the original system's method): tournament selection,
/// simulated binary crossover (SBX), polynomial mutation, elitism. Generation 0 is `population`
/// random individuals; each later generation asks for `population - elites` children, and the
/// elites (the best individuals so far) keep their fitness without being evaluated again.
struct GaOptions {
    int population = 50;  ///< individuals per generation, >= 4
    int elites = 2;       ///< best individuals carried over unevaluated, in [0, population - 2]
    int tournament = 3;   ///< individuals per tournament, in [2, population]
    double crossover_rate = 0.9;  ///< probability that two parents are crossed, in [0, 1]
    double crossover_eta = 15.0;  ///< SBX distribution index (larger: children nearer parents), > 0
    double mutation_rate = -1.0;  ///< probability per gene, in [0, 1]; negative: 1 / dimensions
    double mutation_eta = 20.0;   ///< polynomial mutation index (larger: smaller steps), > 0
    std::vector<double> initial;  ///< parameter units; if given, individual 0 of generation 0
};

/// CMA-ES, (mu/mu_w, lambda) with rank-one and rank-mu updates of the covariance and cumulative
/// step-size adaptation, as in Hansen's tutorial (arXiv:1604.00772), in the normalised space.
/// Points outside the ranges are evaluated clamped into them and ranked with a penalty that
/// grows with their squared distance outside (the tutorial's repair-and-penalise).
struct CmaesOptions {
    int population = 0;           ///< lambda, >= 4; 0: 4 + floor(3 ln dimensions)
    double sigma = 0.3;           ///< initial step size, in range widths (0, 1]
    std::vector<double> initial;  ///< parameter units; the initial mean (default: centre)
};

/// PGPE, policy gradients with parameter-based exploration (Sehnke et al. 2010): symmetric
/// samples mean +- epsilon, a moving-average baseline, the mean and per-parameter deviations
/// following the reward gradient, rewards normalised by the best reward seen.
struct PgpeOptions {
    int population = 20;               ///< individuals per generation (pairs), even, >= 2
    double learning_rate_mean = 0.2;   ///< alpha_mu, > 0
    double learning_rate_sigma = 0.1;  ///< alpha_sigma, >= 0
    double sigma = 0.2;                ///< initial deviation, in range widths (0, 1]
    double baseline_decay = 0.9;       ///< the baseline's moving-average factor, in [0, 1)
    std::vector<double> initial;       ///< parameter units; the initial mean (default: centre)
};

/// The methods, for `parameters` (validate_parameters) and a seed. Throw Error naming the first
/// bad option or parameter.
std::unique_ptr<Method> make_ga(std::vector<Parameter> parameters, const GaOptions& options,
                                std::uint64_t seed);
std::unique_ptr<Method> make_cmaes(std::vector<Parameter> parameters, const CmaesOptions& options,
                                   std::uint64_t seed);
std::unique_ptr<Method> make_pgpe(std::vector<Parameter> parameters, const PgpeOptions& options,
                                  std::uint64_t seed);

/// The method a save() text describes, continuing where it was. `source` names the text in
/// messages (a file name); throws Error "SOURCE: ..." when the text is not such a state.
std::unique_ptr<Method> load_method(const std::string& json, const std::string& source = "state");

}  // namespace gaitlab::optimize
