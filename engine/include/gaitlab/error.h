// Exceptions thrown by the engine. Messages are lowercase, without a trailing period, and say
// what was expected, so the Lua layer can pass them on unchanged.
#pragma once

#include <stdexcept>
#include <string>

namespace gaitlab {

/// Any failure reported by gaitlab.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A spec (robot, world, simulation options, controller parameter) failed validation.
class SpecError : public Error {
  public:
    using Error::Error;
};

/// The simulation diverged (NaN or exploding state); the message names the time and body.
class DivergenceError : public Error {
  public:
    using Error::Error;
};

}  // namespace gaitlab
