#include "method_base.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "gaitlab/error.h"

namespace gaitlab::optimize {
namespace detail {

namespace {
constexpr const char* kFormat = "gaitlab-optimize-state";
constexpr int kVersion = 1;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

const Json& member(const Json& j, const char* key) {
    if (!j.is_object()) throw Error(fmt::format("'{}': expected an object around it", key));
    auto it = j.find(key);
    if (it == j.end()) throw Error(fmt::format("'{}': missing", key));
    return *it;
}

double to_number(const Json& v, const char* key) {
    if (v.is_null()) return kNaN;
    if (!v.is_number()) throw Error(fmt::format("'{}': expected a number, got {}", key, v.dump()));
    return v.get<double>();
}
}  // namespace

std::vector<std::size_t> ranking(const Vector& key) {
    std::vector<std::size_t> order(key.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (std::isnan(key[b])) return !std::isnan(key[a]);
        if (std::isnan(key[a])) return false;
        return key[a] > key[b];
    });
    return order;
}

Json number_json(double v) {
    return std::isnan(v) ? Json(nullptr) : Json(v);
}

Json vector_json(const Vector& v) {
    Json j = Json::array();
    for (double x : v)
        j.push_back(number_json(x));
    return j;
}

Json points_json(const Points& p) {
    Json j = Json::array();
    for (const Vector& v : p)
        j.push_back(vector_json(v));
    return j;
}

double read_number(const Json& j, const char* key) {
    return to_number(member(j, key), key);
}

double read_finite(const Json& j, const char* key) {
    const double v = read_number(j, key);
    if (!std::isfinite(v)) throw Error(fmt::format("'{}': expected a finite number", key));
    return v;
}

std::int64_t read_integer(const Json& j, const char* key, std::int64_t lo, std::int64_t hi) {
    const Json& v = member(j, key);
    if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi)
        throw Error(fmt::format("'{}': expected a whole number in [{}, {}], got {}", key, lo, hi,
                                v.dump()));
    return v.get<std::int64_t>();
}

bool read_bool(const Json& j, const char* key) {
    const Json& v = member(j, key);
    if (!v.is_boolean()) throw Error(fmt::format("'{}': expected true or false", key));
    return v.get<bool>();
}

static Vector to_vector(const Json& v, const char* key, std::size_t n) {
    if (!v.is_array() || v.size() != n)
        throw Error(fmt::format("'{}': expected a list of {} numbers", key, n));
    Vector out;
    for (const Json& x : v)
        out.push_back(to_number(x, key));
    return out;
}

Vector read_vector(const Json& j, const char* key, std::size_t n) {
    return to_vector(member(j, key), key, n);
}

Points read_points(const Json& j, const char* key, std::size_t n) {
    const Json& v = member(j, key);
    if (!v.is_array()) throw Error(fmt::format("'{}': expected a list of lists", key));
    Points out;
    for (const Json& x : v)
        out.push_back(to_vector(x, key, n));
    return out;
}

Json parameters_json(const std::vector<Parameter>& parameters) {
    Json j = Json::array();
    for (const Parameter& p : parameters)
        j.push_back({{"name", p.name}, {"min", p.min}, {"max", p.max}, {"integer", p.integer}});
    return j;
}

std::vector<Parameter> read_parameters(const Json& j) {
    const Json& list = member(j, "parameters");
    if (!list.is_array()) throw Error("'parameters': expected a list");
    std::vector<Parameter> out;
    for (const Json& p : list) {
        Parameter q;
        const Json& name = member(p, "name");
        if (!name.is_string()) throw Error("'name': expected a string");
        q.name = name.get<std::string>();
        q.min = read_finite(p, "min");
        q.max = read_finite(p, "max");
        q.integer = read_bool(p, "integer");
        out.push_back(q);
    }
    validate_parameters(out);
    return out;
}

Vector initial_point(const std::vector<Parameter>& parameters, const Vector& initial,
                     const char* method) {
    if (initial.empty()) return Vector(parameters.size(), 0.5);
    if (initial.size() != parameters.size())
        throw Error(fmt::format("{}: initial has {} values (expected one per parameter: {})",
                                method, initial.size(), parameters.size()));
    try {
        return encode(parameters, initial);
    } catch (const Error& e) {
        throw Error(fmt::format("{}: initial point: {}", method, e.what()));
    }
}

MethodBase::MethodBase(std::string name, std::vector<Parameter> parameters, std::uint64_t seed)
    : random_(seed),
      name_(std::move(name)),
      parameters_(std::move(parameters)),
      seed_(seed),
      best_fitness_(kNaN) {
    validate_parameters(parameters_);
}

const Points& MethodBase::ask() {
    if (!asked_) {
        pending_u_ = sample();
        pending_x_.clear();
        for (const Vector& u : pending_u_)
            pending_x_.push_back(decode(parameters_, u));
        asked_ = true;
    }
    return pending_x_;
}

void MethodBase::tell(const Vector& fitness) {
    if (!asked_)
        throw Error(fmt::format("{}: tell() before ask() (generation {} has no individuals yet)",
                                name_, generation_));
    if (fitness.size() != pending_x_.size())
        throw Error(fmt::format(
            "{}: expected {} fitness values (one per individual of generation {}, in ask "
            "order), got {}",
            name_, pending_x_.size(), generation_, fitness.size()));
    Vector f(fitness);
    for (double& v : f)
        if (!std::isfinite(v)) v = kNaN;
    for (std::size_t i = 0; i < f.size(); ++i)
        if (!std::isnan(f[i]) && (std::isnan(best_fitness_) || f[i] > best_fitness_)) {
            best_fitness_ = f[i];
            best_ = pending_x_[i];
        }
    update(pending_u_, f);
    evaluations_ += static_cast<std::int64_t>(f.size());
    ++generation_;
    asked_ = false;
    pending_u_.clear();
    pending_x_.clear();
}

std::string MethodBase::save() const {
    Json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    j["method"] = name_;
    j["parameters"] = parameters_json(parameters_);
    j["seed"] = seed_;
    j["options"] = options_json();
    j["generation"] = generation_;
    j["evaluations"] = evaluations_;
    j["best"] = vector_json(best_);
    j["best_fitness"] = number_json(best_fitness_);
    j["asked"] = asked_;
    j["pending"] = points_json(pending_u_);
    j["random"] = random_.state();
    j["state"] = state_json();
    return j.dump(1) + "\n";
}

void MethodBase::load(const Json& j) {
    generation_ = static_cast<int>(read_integer(j, "generation", 0, INT32_MAX));
    evaluations_ = read_integer(j, "evaluations", 0, INT64_MAX);
    const Json& best = member(j, "best");
    best_ = best.is_array() && best.empty() ? Vector{} : read_vector(j, "best", dimensions());
    best_fitness_ = read_number(j, "best_fitness");
    if (best_.empty() != std::isnan(best_fitness_))
        throw Error("'best': expected a point exactly when 'best_fitness' is a number");
    asked_ = read_bool(j, "asked");
    pending_u_ = read_points(j, "pending", dimensions());
    if (asked_ == pending_u_.empty())
        throw Error("'pending': expected individuals exactly when 'asked' is true");
    pending_x_.clear();
    for (Vector& u : pending_u_) {
        for (double v : u)
            if (!std::isfinite(v)) throw Error("'pending': expected finite numbers");
        pending_x_.push_back(decode(parameters_, u));
    }
    const Json& random = member(j, "random");
    if (!random.is_string()) throw Error("'random': expected the random stream's state text");
    try {
        random_.set_state(random.get<std::string>());
    } catch (const Error& e) {
        throw Error(fmt::format("'random': {}", e.what()));
    }
    load_state(member(j, "state"));
}

}  // namespace detail

std::unique_ptr<Method> load_method(const std::string& text, const std::string& source) {
    using namespace detail;
    try {
        const Json j = Json::parse(text);
        const Json& format = member(j, "format");
        if (!format.is_string() || format.get<std::string>() != kFormat)
            throw Error(fmt::format("'format': expected \"{}\"", kFormat));
        const std::int64_t version = read_integer(j, "version", 0, INT32_MAX);
        if (version != kVersion)
            throw Error(fmt::format("'version': {} is not known (expected {})", version, kVersion));
        const Json& method = member(j, "method");
        const Json& seed = member(j, "seed");
        if (!seed.is_number_unsigned()) throw Error("'seed': expected a whole number >= 0");
        std::vector<Parameter> parameters = read_parameters(j);
        const Json& options = member(j, "options");
        const std::uint64_t s = seed.get<std::uint64_t>();
        std::unique_ptr<MethodBase> m;
        if (method == "ga")
            m = make_saved_ga(std::move(parameters), options, s);
        else if (method == "cmaes")
            m = make_saved_cmaes(std::move(parameters), options, s);
        else if (method == "pgpe")
            m = make_saved_pgpe(std::move(parameters), options, s);
        else
            throw Error(fmt::format(
                "'method': {} is not one (expected \"ga\", \"cmaes\" or \"pgpe\")", method.dump()));
        m->load(j);
        return m;
    } catch (const Json::exception& e) {
        throw Error(fmt::format("{}: not an optimizer state: {}", source, e.what()));
    } catch (const Error& e) {
        throw Error(fmt::format("{}: not an optimizer state: {}", source, e.what()));
    }
}

}  // namespace gaitlab::optimize
