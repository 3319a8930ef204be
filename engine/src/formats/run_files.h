// Files of run folders: files that grow by appending (whole files are read and written with
// gaitlab/files.h). Every failure is an IoError naming the path and the reason.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gaitlab::formats {

/// "No space left on device" for ENOSPC ...
std::string reason(int error_number);

/// Writes all of `bytes` to the file descriptor `fd` (retrying after signals); throws IoError
/// naming `path`.
void write_all(int fd, std::string_view bytes, const std::string& path);

/// The kernel's id of this boot (/proc/sys/kernel/random/boot_id), "" if unknown.
std::string boot_id();

/// When process `pid` started, in clock ticks after boot (field 22 of /proc/PID/stat); 0 if
/// there is no such process or it cannot be told.
std::uint64_t process_start_time(long pid);

/// The FNV-1a 64-bit hash of `bytes` as run.json records it: "fnv1a64:" and 16 lowercase hex
/// digits (FNV-1a: offset basis 0xcbf29ce484222325, prime 0x100000001b3; a check that a file
/// is the one that ran, not a defence against forgery).
std::string content_hash(std::string_view bytes);

/// A file opened for appending (created or truncated on open). Writes go straight to the
/// operating system (write(2), no fsync): once write() returns they survive the process, not
/// a power loss.
class AppendFile {
  public:
    AppendFile() = default;
    /// Creates or truncates `path`; throws IoError.
    explicit AppendFile(std::string path);
    ~AppendFile();
    AppendFile(AppendFile&& other) noexcept;
    AppendFile& operator=(AppendFile&& other) noexcept;
    AppendFile(const AppendFile&) = delete;
    AppendFile& operator=(const AppendFile&) = delete;

    /// Writes all of `bytes`; throws IoError (a full disk: "No space left on device").
    void write(std::string_view bytes);
    void close();
    bool is_open() const { return fd_ >= 0; }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
    int fd_ = -1;
};

}  // namespace gaitlab::formats
