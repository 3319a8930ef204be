#include "formats/run_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "gaitlab/error.h"

namespace gaitlab::formats {

std::string reason(int error_number) {
    return std::strerror(error_number);
}

void write_all(int fd, std::string_view bytes, const std::string& path) {
    const char* p = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw IoError(fmt::format("cannot write {}: {}", path, reason(errno)));
        }
        p += n;
        left -= static_cast<size_t>(n);
    }
}

namespace {

// a small file of /proc, "" if it cannot be read (they are regular files that say they are
// empty: read until the end, never more than `limit` bytes)
std::string read_proc(const std::string& path, size_t limit = 4096) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return "";
    std::string out;
    char buf[1024];
    while (out.size() < limit) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        out.append(buf, static_cast<size_t>(n));
    }
    ::close(fd);
    return out;
}

}  // namespace

std::string boot_id() {
    std::string id = read_proc("/proc/sys/kernel/random/boot_id", 64);
    while (!id.empty() && (id.back() == '\n' || id.back() == ' '))
        id.pop_back();
    return id;
}

std::uint64_t process_start_time(long pid) {
    if (pid <= 0) return 0;
    const std::string stat = read_proc(fmt::format("/proc/{}/stat", pid));
    // "PID (COMM) STATE PPID ...": COMM may hold spaces and parentheses, so fields are counted
    // from the last ')'; the start time is field 22, the 20th after it
    const size_t paren = stat.rfind(')');
    if (paren == std::string::npos) return 0;
    size_t i = paren + 1;
    for (int field = 3; field <= 22; ++field) {
        while (i < stat.size() && stat[i] == ' ')
            ++i;
        const size_t start = i;
        while (i < stat.size() && stat[i] != ' ')
            ++i;
        if (field == 22) {
            std::uint64_t v = 0;
            const auto r = std::from_chars(stat.data() + start, stat.data() + i, v);
            return r.ec == std::errc() ? v : 0;
        }
    }
    return 0;
}

AppendFile::AppendFile(std::string path) : path_(std::move(path)) {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError(fmt::format("cannot write {}: {}", path_, reason(errno)));
}

AppendFile::~AppendFile() {
    close();
}

AppendFile::AppendFile(AppendFile&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_) {
    other.fd_ = -1;
}

AppendFile& AppendFile::operator=(AppendFile&& other) noexcept {
    if (this != &other) {
        close();
        path_ = std::move(other.path_);
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

void AppendFile::write(std::string_view bytes) {
    if (fd_ < 0) throw IoError(fmt::format("cannot write {}: the file is closed", path_));
    write_all(fd_, bytes, path_);
}

void AppendFile::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

std::string content_hash(std::string_view bytes) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char c : bytes) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    return fmt::format("fnv1a64:{:016x}", h);
}

}  // namespace gaitlab::formats
