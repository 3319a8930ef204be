// Reading and writing whole files. Reads are bounded and refuse what is not a regular file, so
// no input (a FIFO, /dev/zero, a directory, a huge file) blocks or exhausts gaitlab; writes are
// atomic, so a reader never sees half of one (configuration files, run metadata, templates).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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

/// A file that could not be written: "cannot write PATH: REASON". When the file is one part
/// of a save that writes several (a simulation file and the robot, actuation and environment
/// files next to it), PATH is the file asked for and the part is named too: "cannot write
/// PATH: its part PART: REASON". When a folder above it could not be created: "cannot write
/// PATH: cannot create folder FOLDER: REASON".
class WriteError : public IoError {
  public:
    WriteError(std::string path, std::string reason, std::string folder = {},
               std::string part = {});
    /// The file asked for.
    const std::string& path() const { return path_; }
    /// Why, without a path: "Permission denied", "No space left on device", ...
    const std::string& reason() const { return reason_; }
    /// The folder that could not be created ("" if the file itself failed).
    const std::string& folder() const { return folder_; }
    /// The part of the save that failed ("" if the file itself, or its folder, failed).
    const std::string& part() const { return part_; }

  private:
    std::string path_, reason_, folder_, part_;
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

/// What a writer does when the folder of the file it writes does not exist.
enum class MissingFolders {
    refuse,  ///< fail: "cannot write PATH: No such file or directory"
    create   ///< create it and the folders above it, as `mkdir -p` does
};

/// Creates the folders above `path` that do not exist yet, as `mkdir -p` does (mode 0777 less
/// the umask). Throws WriteError naming `path` and the first folder that could not be created
/// (a file in the way: "exists and is not a folder").
void create_folders_above(const std::string& path);

/// Writes `text` to `path` atomically: into a temporary file in the same folder, flushed, then
/// renamed over `path`. On failure nothing at `path` changes and WriteError names the path
/// (never the temporary file). With MissingFolders::create, missing folders above `path` are
/// created first (they stay if the write then fails).
void write_file_atomic(const std::string& path, std::string_view text,
                       MissingFolders folders = MissingFolders::refuse);

/// Writes several files, each as write_file_atomic does, all or none: every text is written to
/// its temporary file first, and only when all of them are written are they renamed over their
/// paths. A failure before the renames (a folder in the way, a full disk) leaves every path as
/// it was and throws WriteError naming the path it failed on. (The renames themselves fail
/// only when the folder changes under them.)
void write_files_atomic(const std::vector<std::pair<std::string, std::string>>& files,
                        MissingFolders folders = MissingFolders::refuse);

}  // namespace gaitlab
