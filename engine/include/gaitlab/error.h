// Exceptions thrown by the engine. Messages are lowercase, without a trailing period, and say
// what was expected, so the Lua layer can pass them on unchanged.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace gaitlab {

/// Any failure reported by gaitlab. A message travels as a C string (what(), Lua's error
/// messages), so a NUL byte in it, which a user's string may hold, is written as \x00 rather
/// than cutting the message short there (as gaitlab/terminal.h writes it for the terminal,
/// with the other control characters).
class Error : public std::runtime_error {
  public:
    explicit Error(const std::string& message) : std::runtime_error(printable(message)) {}
    explicit Error(const char* message) : std::runtime_error(message) {}

    /// `message` with each NUL byte written as the four characters \x00.
    static std::string printable(const std::string& message) {
        if (message.find('\0') == std::string::npos) return message;
        std::string out;
        out.reserve(message.size() + 8);
        for (char c : message) {
            if (c == '\0') {
                out += "\\x00";
            } else {
                out += c;
            }
        }
        return out;
    }
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

/// A file or folder could not be created, read or written; the message names it and says why.
class IoError : public Error {
  public:
    using Error::Error;
};

/// A file does not hold what was expected; the message names FILE:LINE and the expected form
/// (configuration files add the element path: "FILE:LINE: PATH: message").
class FormatError : public Error {
  public:
    explicit FormatError(const std::string& message, std::string file = {}, int line = 0)
        : Error(message), file_(std::move(file)), line_(line) {}
    /// The file and line the message names ("" and 0 when unknown).
    const std::string& file() const { return file_; }
    int line() const { return line_; }

  private:
    std::string file_;
    int line_;
};

}  // namespace gaitlab
