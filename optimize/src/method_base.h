// What the three methods share: the ask/tell bookkeeping (the pending generation, counts, the
// best individual), the random stream, ranking with failures last, and the JSON state file.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "gaitlab/optimize/method.h"
#include "gaitlab/optimize/random.h"

namespace gaitlab::optimize::detail {

using Json = nlohmann::ordered_json;
using Vector = std::vector<double>;
using Points = std::vector<Vector>;

/// The indices of `key` from best (largest) to worst, NaN last; equal keys keep index order.
std::vector<std::size_t> ranking(const Vector& key);

/// A double as JSON: NaN becomes null (JSON has no NaN); finite values round-trip exactly.
Json number_json(double v);

// readers of a state's JSON: each throws Error "'KEY': expected ..." when the value is missing
// or of another form
double read_number(const Json& j, const char* key);  // a number or null (NaN)
double read_finite(const Json& j, const char* key);
std::int64_t read_integer(const Json& j, const char* key, std::int64_t lo, std::int64_t hi);
bool read_bool(const Json& j, const char* key);
Vector read_vector(const Json& j, const char* key, std::size_t n);  // n numbers (null = NaN)
Points read_points(const Json& j, const char* key, std::size_t n);  // lists of n numbers
Json vector_json(const Vector& v);
Json points_json(const Points& p);

class MethodBase : public Method {
  public:
    MethodBase(std::string name, std::vector<Parameter> parameters, std::uint64_t seed);

    const std::string& name() const override { return name_; }
    const std::vector<Parameter>& parameters() const override { return parameters_; }
    const Points& ask() override;
    void tell(const Vector& fitness) override;
    int generation() const override { return generation_; }
    std::int64_t evaluations() const override { return evaluations_; }
    const Vector& best() const override { return best_; }
    double best_fitness() const override { return best_fitness_; }
    std::string save() const override;

    /// Restores what save() wrote into this method, made by make_* with the saved options.
    void load(const Json& j);

  protected:
    std::size_t dimensions() const { return parameters_.size(); }

    /// The next generation in the method's normalised coordinates (decode() gives the points).
    virtual Points sample() = 0;
    /// Learns from the generation sample() gave; `fitness` has NaN for every failure.
    virtual void update(const Points& u, const Vector& fitness) = 0;
    virtual Json options_json() const = 0;
    virtual Json state_json() const = 0;
    virtual void load_state(const Json& state) = 0;

    Random random_;

  private:
    std::string name_;
    std::vector<Parameter> parameters_;
    std::uint64_t seed_;
    int generation_ = 0;
    std::int64_t evaluations_ = 0;
    Vector best_;
    double best_fitness_;
    bool asked_ = false;
    Points pending_u_;
    Points pending_x_;
};

/// The parameters as JSON and back (load_method checks them with validate_parameters).
Json parameters_json(const std::vector<Parameter>& parameters);
std::vector<Parameter> read_parameters(const Json& j);

// load_method's per-method halves: the method made from its saved options, not yet loaded
std::unique_ptr<MethodBase> make_saved_ga(std::vector<Parameter> p, const Json& options,
                                          std::uint64_t seed);
std::unique_ptr<MethodBase> make_saved_cmaes(std::vector<Parameter> p, const Json& options,
                                             std::uint64_t seed);
std::unique_ptr<MethodBase> make_saved_pgpe(std::vector<Parameter> p, const Json& options,
                                            std::uint64_t seed);

/// The initial point of `options.initial` in normalised coordinates, or the centre when empty.
Vector initial_point(const std::vector<Parameter>& parameters, const Vector& initial,
                     const char* method);

}  // namespace gaitlab::optimize::detail
