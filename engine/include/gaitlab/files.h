// Reading and writing whole files. Reads are bounded and refuse what is not a regular file, so
// no input (a FIFO, /dev/zero, a directory, a huge file) blocks or exhausts gaitlab; writes are
// atomic, so a reader never sees half of one (configuration files, run metadata, templates).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "gaitlab/error.h"

namespace gaitlab {

/// The largest input gaitlab reads whole by default (scripts, controller files, configuration
/// files, images, run metadata): 64 MiB.
inline constexpr std::uintmax_t kMaxInputBytes = std::uintmax_t{64} << 20;

/// A file that could not be read: "cannot read PATH: REASON".
class ReadError : public IoError {
  public:
    ReadError(const std::string& path, std::string reason)
        : IoError("cannot read " + path + ": " + reason), reason_(std::move(reason)) {}
    /// Why, without the path: "No such file or directory", "is a directory", ...
    const std::string& reason() const { return reason_; }

  private:
    std::string reason_;
};

/// The whole of the regular file at `path`, at most `max_bytes` long. Anything else is refused
/// up front with ReadError naming the path: a missing file ("no such file"), a directory ("is a
/// directory"), a FIFO, device or socket ("is not a regular file"), a larger file ("is larger
/// than the 64 MiB gaitlab reads"). Never blocks on a FIFO, never reads forever.
std::string read_file(const std::string& path, std::uintmax_t max_bytes = kMaxInputBytes);

/// Refuses up front, as read_file would, what read_file would refuse (no file, a directory, a
/// FIFO, device or socket, a file larger than `max_bytes`), without opening or reading it:
/// for callers that hand the path to a reader of their own. Throws ReadError.
void check_file(const std::string& path, std::uintmax_t max_bytes = kMaxInputBytes);

/// "64 MiB", "512 KiB", "100 bytes": a size limit as messages state it.
std::string describe_size(std::uintmax_t bytes);

/// Writes `text` to `path` atomically: into a temporary file in the same folder, flushed, then
/// renamed over `path`. On failure nothing at `path` changes and IoError names the path.
void write_file_atomic(const std::string& path, std::string_view text);

}  // namespace gaitlab
