#include "gaitlab/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "data/files.h"

namespace gaitlab {

using data::reason;
using data::write_all;

std::string describe_size(std::uintmax_t bytes) {
    if (bytes >= (std::uintmax_t{1} << 30) && bytes % (std::uintmax_t{1} << 30) == 0)
        return fmt::format("{} GiB", bytes >> 30);
    if (bytes >= (std::uintmax_t{1} << 20) && bytes % (std::uintmax_t{1} << 20) == 0)
        return fmt::format("{} MiB", bytes >> 20);
    if (bytes >= 1024 && bytes % 1024 == 0) return fmt::format("{} KiB", bytes >> 10);
    return fmt::format("{} bytes", bytes);
}

namespace {

ReadError too_large(const std::string& path, std::uintmax_t max_bytes) {
    return ReadError(path, "larger than the " + describe_size(max_bytes) + " gaitlab reads");
}

// what read_file and check_file refuse, from the file's status
void refuse(const std::string& path, const struct stat& st, std::uintmax_t max_bytes) {
    if (S_ISDIR(st.st_mode)) throw ReadError(path, "is a directory");
    if (!S_ISREG(st.st_mode)) {
        throw ReadError(path, "not a regular file (a FIFO, device or socket)");
    }
    if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large(path, max_bytes);
}

}  // namespace

void check_file(const std::string& path, std::uintmax_t max_bytes) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw ReadError(path, reason(errno));
    refuse(path, st, max_bytes);
}

std::string read_file(const std::string& path, std::uintmax_t max_bytes) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw ReadError(path, reason(errno));
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw ReadError(path, reason(errno));
    refuse(path, st, max_bytes);
    // a regular file may still grow while it is read (or lie about its size, as /proc does):
    // read at most one byte past the limit
    std::string out;
    out.reserve(static_cast<size_t>(st.st_size));
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN) continue;
            throw ReadError(path, reason(errno));
        }
        if (n == 0) break;
        out.append(buf, static_cast<size_t>(n));
        if (out.size() > max_bytes) throw too_large(path, max_bytes);
    }
    return out;
}

void write_file_atomic(const std::string& path, std::string_view text) {
    // the file replaced: a link's target (links stay links); never what is not a regular file
    // (renaming over /dev/full would replace the device with a file)
    std::string target = path;
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        if (char* real = ::realpath(path.c_str(), nullptr)) {
            target = real;
            std::free(real);
        }
    }
    if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        throw IoError(fmt::format("cannot write {}: {}", path,
                                  S_ISDIR(st.st_mode)
                                      ? "is a directory"
                                      : "not a regular file (a FIFO, device or socket)"));
    }
    // a temporary name of this process and call: two writers of one path never share it, and
    // O_EXCL never follows a link someone left at that name
    static std::atomic<unsigned> counter{0};
    const std::string tmp =
        fmt::format("{}.tmp-{}-{}", target, static_cast<long>(::getpid()), counter++);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(fmt::format("cannot write {}: {}", path, reason(errno)));
    try {
        write_all(fd, text, path);
    } catch (...) {
        ::close(fd);
        std::remove(tmp.c_str());
        throw;
    }
    if (::close(fd) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw IoError(fmt::format("cannot write {}: {}", path, reason(e)));
    }
    if (std::rename(tmp.c_str(), target.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw IoError(fmt::format("cannot write {}: {}", path, reason(e)));
    }
}

}  // namespace gaitlab
