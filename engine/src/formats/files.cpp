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

#include "formats/run_files.h"

namespace gaitlab {

using formats::reason;

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

WriteError::WriteError(std::string path, std::string reason, std::string folder, std::string part)
    : IoError(fmt::format("cannot write {}: {}{}{}", path,
                          part.empty() ? "" : "its part " + part + ": ",
                          folder.empty() ? "" : "cannot create folder " + folder + ": ", reason)),
      path_(std::move(path)),
      reason_(std::move(reason)),
      folder_(std::move(folder)),
      part_(std::move(part)) {}

void create_folders_above(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    // one folder at a time from the top, as mkdir -p does, so the message names the one that
    // could not be made
    std::filesystem::path folder;
    for (const std::filesystem::path& part : parent) {
        folder /= part;
        const std::string f = folder.string();
        struct stat st {};
        if (::stat(f.c_str(), &st) == 0) {
            if (S_ISDIR(st.st_mode)) continue;
            throw WriteError(path, "a file of that name is in the way", f);
        }
        if (::mkdir(f.c_str(), 0777) == 0) continue;
        const int e = errno;
        if (e == EEXIST) {
            // made meanwhile by someone else: fine if it is a folder; else a dangling link
            if (::stat(f.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) continue;
            throw WriteError(path, "a file of that name is in the way", f);
        }
        throw WriteError(path, reason(e), f);
    }
}

namespace {

// a file written to its temporary name, not yet renamed over its path
struct Staged {
    std::string path;    // as given, for messages
    std::string target;  // what the rename replaces: the path, or a link's target
    std::string tmp;
};

Staged stage(const std::string& path, std::string_view text, MissingFolders folders) {
    if (folders == MissingFolders::create) create_folders_above(path);
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
        throw WriteError(path, S_ISDIR(st.st_mode)
                                   ? "is a directory"
                                   : "not a regular file (a FIFO, device or socket)");
    }
    // a temporary name of this process and call: two writers of one path never share it, and
    // O_EXCL never follows a link someone left at that name; messages name `path`, never it
    static std::atomic<unsigned> counter{0};
    const std::string suffix = fmt::format(".tmp-{}-{}", static_cast<long>(::getpid()), counter++);
    // a name near the file system's 255 bytes is cut to leave room for the suffix (bytes, not
    // characters: the name lives for one rename)
    const std::filesystem::path t(target);
    std::string name = t.filename().string();
    constexpr size_t kMaxName = 255;
    if (name.size() + suffix.size() > kMaxName) name.resize(kMaxName - suffix.size());
    const std::string tmp = (t.parent_path() / (name + suffix)).string();
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw WriteError(path, reason(errno));
    const auto fail = [&](int e) {
        std::remove(tmp.c_str());
        throw WriteError(path, reason(e));
    };
    for (size_t done = 0; done < text.size();) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(fd);
            fail(e);
        }
        done += static_cast<size_t>(n);
    }
    if (::close(fd) != 0) fail(errno);
    return {path, target, tmp};
}

void commit(const Staged& s) {
    if (std::rename(s.tmp.c_str(), s.target.c_str()) != 0) {
        const int e = errno;
        std::remove(s.tmp.c_str());
        throw WriteError(s.path, reason(e));
    }
}

}  // namespace

void write_file_atomic(const std::string& path, std::string_view text, MissingFolders folders) {
    commit(stage(path, text, folders));
}

void write_files_atomic(const std::vector<std::pair<std::string, std::string>>& files,
                        MissingFolders folders) {
    std::vector<Staged> staged;
    staged.reserve(files.size());
    try {
        for (const auto& [path, text] : files)
            staged.push_back(stage(path, text, folders));
    } catch (...) {
        for (const Staged& s : staged)
            std::remove(s.tmp.c_str());
        throw;
    }
    for (size_t i = 0; i < staged.size(); ++i) {
        try {
            commit(staged[i]);
        } catch (...) {
            for (size_t j = i + 1; j < staged.size(); ++j)
                std::remove(staged[j].tmp.c_str());
            throw;
        }
    }
}

}  // namespace gaitlab
