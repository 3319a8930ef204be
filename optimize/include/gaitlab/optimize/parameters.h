// The search space of an optimization: named real parameters, each with a closed range, some
// of them integers. Methods search a normalised space (each parameter's range mapped onto
// [0, 1]) and hand out points in parameter units: clamped into the ranges, integers rounded.
#pragma once

#include <string>
#include <vector>

namespace gaitlab::optimize {

/// One parameter to tune.
struct Parameter {
    std::string name;      ///< unique, non-empty (evaluations.jsonl and actuation files use it)
    double min = 0.0;      ///< lower bound, in the parameter's unit; finite
    double max = 1.0;      ///< upper bound, in the parameter's unit; finite, greater than min
    bool integer = false;  ///< values are whole numbers: the point is rounded to the nearest one
};

/// Checks a list of parameters: at least one, names non-empty and unique, ranges finite and
/// not empty (min < max; for an integer, at least two whole numbers in it). Throws Error
/// "parameter 'NAME': WHAT (expected ...)" naming the first bad one.
void validate_parameters(const std::vector<Parameter>& parameters);

/// The point in parameter units for a point `u` of the normalised space (u = 0 is min, 1 is
/// max): clamped into the ranges, integer parameters rounded half away from zero into theirs.
std::vector<double> decode(const std::vector<Parameter>& parameters, const std::vector<double>& u);

/// The normalised point for a point `x` in parameter units (x = min gives 0, max gives 1). Throws
/// Error when a value is not finite or lies outside its range, naming the parameter.
std::vector<double> encode(const std::vector<Parameter>& parameters, const std::vector<double>& x);

}  // namespace gaitlab::optimize
