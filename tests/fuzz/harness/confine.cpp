// The interposed file functions of confine.h. Each one decides whether its call writes, and
// whether the path it writes lies inside the folder, then calls the C library's own function
// (found with dlsym(RTLD_NEXT)) or fails with EACCES. Paths are compared lexically: the folder
// is a fresh directory that the scripts cannot put symbolic links in (symlink and link are
// refused outside it too, and nothing else makes links).
#undef _FORTIFY_SOURCE
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include "confine.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace gaitlab::fuzz {

namespace {

std::atomic<bool> active{false};
std::string folder;                // written only while inactive
std::vector<std::string> allowed;  // the same
std::mutex refused_mutex;
std::vector<std::string> refused;

// the directory a relative path of a *at() call starts from
std::string base_dir(int dirfd) {
    char buf[4096];
    if (dirfd == AT_FDCWD) {
        return getcwd(buf, sizeof buf) ? std::string(buf) : std::string();
    }
    const std::string link = "/proc/self/fd/" + std::to_string(dirfd);
    const ssize_t n = readlink(link.c_str(), buf, sizeof buf - 1);
    return n > 0 ? std::string(buf, static_cast<size_t>(n)) : std::string();
}

// `path` made absolute against `dirfd` and normalized: no ".", "..", or repeated '/'
std::string absolute(int dirfd, const char* path) {
    std::string full = path[0] == '/' ? std::string(path) : base_dir(dirfd) + "/" + path;
    std::vector<std::string> parts;
    size_t i = 0;
    while (i < full.size()) {
        size_t j = full.find('/', i);
        if (j == std::string::npos) j = full.size();
        const std::string part = full.substr(i, j - i);
        if (part == "..") {
            if (!parts.empty()) parts.pop_back();
        } else if (!part.empty() && part != ".") {
            parts.push_back(part);
        }
        i = j + 1;
    }
    std::string out;
    for (const std::string& p : parts)
        out += "/" + p;
    return out.empty() ? "/" : out;
}

// whether `path` is `dir` or inside it
bool inside(const std::string& path, const std::string& dir) {
    if (dir == "/") return true;
    return path.compare(0, dir.size(), dir) == 0 &&
           (path.size() == dir.size() || path[dir.size()] == '/');
}

// whether a write of `path` (relative to dirfd) may go ahead; notes it when it may not
bool may_write(const char* call, int dirfd, const char* path) {
    if (!active.load() || path == nullptr || path[0] == '\0') return true;
    const std::string p = absolute(dirfd, path);
    if (inside(p, folder)) return true;
    for (const std::string& a : allowed) {
        if (inside(p, a)) return true;
    }
    {
        std::lock_guard<std::mutex> lock(refused_mutex);
        refused.push_back(std::string(call) + " " + p);
    }
    errno = EACCES;
    return false;
}

bool writes(int flags) {
    return (flags & O_ACCMODE) != O_RDONLY || (flags & (O_CREAT | O_TRUNC)) != 0;
}

bool writes(const char* mode) {
    return mode != nullptr && std::strpbrk(mode, "wa+") != nullptr;
}

// the C library's function `name`, of type F
template <class F>
F next(const char* name) {
    return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

// the mode argument of open(): present only when the flags create a file
mode_t open_mode(int flags, va_list ap) {
    return (flags & O_CREAT) != 0 || (flags & O_TMPFILE) == O_TMPFILE
               ? static_cast<mode_t>(va_arg(ap, int))
               : 0;
}

}  // namespace

void confine_writes(const std::string& dir) {
    active.store(false);
    folder = dir;
    {
        std::lock_guard<std::mutex> lock(refused_mutex);
        refused.clear();
    }
    active.store(true);
}

void allow_writes_in(const std::string& dir) {
    const bool was = active.exchange(false);
    allowed.push_back(absolute(AT_FDCWD, dir.c_str()));
    active.store(was);
}

void release_writes() {
    active.store(false);
}

std::vector<std::string> refused_writes() {
    std::lock_guard<std::mutex> lock(refused_mutex);
    return refused;
}

}  // namespace gaitlab::fuzz

using gaitlab::fuzz::may_write;
using gaitlab::fuzz::next;
using gaitlab::fuzz::open_mode;
using gaitlab::fuzz::writes;

extern "C" {

int open(const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    const mode_t mode = open_mode(flags, ap);
    va_end(ap);
    static const auto real = next<int (*)(const char*, int, ...)>("open");
    if (writes(flags) && !may_write("open", AT_FDCWD, path)) return -1;
    return real(path, flags, mode);
}

int open64(const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    const mode_t mode = open_mode(flags, ap);
    va_end(ap);
    static const auto real = next<int (*)(const char*, int, ...)>("open64");
    if (writes(flags) && !may_write("open", AT_FDCWD, path)) return -1;
    return real(path, flags, mode);
}

int openat(int dirfd, const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    const mode_t mode = open_mode(flags, ap);
    va_end(ap);
    static const auto real = next<int (*)(int, const char*, int, ...)>("openat");
    if (writes(flags) && !may_write("openat", dirfd, path)) return -1;
    return real(dirfd, path, flags, mode);
}

int openat64(int dirfd, const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    const mode_t mode = open_mode(flags, ap);
    va_end(ap);
    static const auto real = next<int (*)(int, const char*, int, ...)>("openat64");
    if (writes(flags) && !may_write("openat", dirfd, path)) return -1;
    return real(dirfd, path, flags, mode);
}

int creat(const char* path, mode_t mode) {
    static const auto real = next<int (*)(const char*, mode_t)>("creat");
    if (!may_write("creat", AT_FDCWD, path)) return -1;
    return real(path, mode);
}

int creat64(const char* path, mode_t mode) {
    static const auto real = next<int (*)(const char*, mode_t)>("creat64");
    if (!may_write("creat", AT_FDCWD, path)) return -1;
    return real(path, mode);
}

FILE* fopen(const char* path, const char* mode) {
    static const auto real = next<FILE* (*)(const char*, const char*)>("fopen");
    if (writes(mode) && !may_write("fopen", AT_FDCWD, path)) return nullptr;
    return real(path, mode);
}

FILE* fopen64(const char* path, const char* mode) {
    static const auto real = next<FILE* (*)(const char*, const char*)>("fopen64");
    if (writes(mode) && !may_write("fopen", AT_FDCWD, path)) return nullptr;
    return real(path, mode);
}

FILE* freopen(const char* path, const char* mode, FILE* stream) {
    static const auto real = next<FILE* (*)(const char*, const char*, FILE*)>("freopen");
    if (writes(mode) && !may_write("freopen", AT_FDCWD, path)) return nullptr;
    return real(path, mode, stream);
}

FILE* freopen64(const char* path, const char* mode, FILE* stream) {
    static const auto real = next<FILE* (*)(const char*, const char*, FILE*)>("freopen64");
    if (writes(mode) && !may_write("freopen", AT_FDCWD, path)) return nullptr;
    return real(path, mode, stream);
}

int mkdir(const char* path, mode_t mode) {
    static const auto real = next<int (*)(const char*, mode_t)>("mkdir");
    if (!may_write("mkdir", AT_FDCWD, path)) return -1;
    return real(path, mode);
}

int mkdirat(int dirfd, const char* path, mode_t mode) {
    static const auto real = next<int (*)(int, const char*, mode_t)>("mkdirat");
    if (!may_write("mkdirat", dirfd, path)) return -1;
    return real(dirfd, path, mode);
}

int rename(const char* from, const char* to) {
    static const auto real = next<int (*)(const char*, const char*)>("rename");
    if (!may_write("rename", AT_FDCWD, from) || !may_write("rename", AT_FDCWD, to)) return -1;
    return real(from, to);
}

int renameat(int fromfd, const char* from, int tofd, const char* to) {
    static const auto real = next<int (*)(int, const char*, int, const char*)>("renameat");
    if (!may_write("renameat", fromfd, from) || !may_write("renameat", tofd, to)) return -1;
    return real(fromfd, from, tofd, to);
}

int renameat2(int fromfd, const char* from, int tofd, const char* to, unsigned flags) {
    static const auto real =
        next<int (*)(int, const char*, int, const char*, unsigned)>("renameat2");
    if (!may_write("renameat2", fromfd, from) || !may_write("renameat2", tofd, to)) return -1;
    return real(fromfd, from, tofd, to, flags);
}

int unlink(const char* path) {
    static const auto real = next<int (*)(const char*)>("unlink");
    if (!may_write("unlink", AT_FDCWD, path)) return -1;
    return real(path);
}

int unlinkat(int dirfd, const char* path, int flags) {
    static const auto real = next<int (*)(int, const char*, int)>("unlinkat");
    if (!may_write("unlinkat", dirfd, path)) return -1;
    return real(dirfd, path, flags);
}

int rmdir(const char* path) {
    static const auto real = next<int (*)(const char*)>("rmdir");
    if (!may_write("rmdir", AT_FDCWD, path)) return -1;
    return real(path);
}

int remove(const char* path) {
    static const auto real = next<int (*)(const char*)>("remove");
    if (!may_write("remove", AT_FDCWD, path)) return -1;
    return real(path);
}

int truncate(const char* path, off_t length) {
    static const auto real = next<int (*)(const char*, off_t)>("truncate");
    if (!may_write("truncate", AT_FDCWD, path)) return -1;
    return real(path, length);
}

int truncate64(const char* path, off64_t length) {
    static const auto real = next<int (*)(const char*, off64_t)>("truncate64");
    if (!may_write("truncate", AT_FDCWD, path)) return -1;
    return real(path, length);
}

int link(const char* from, const char* to) {
    static const auto real = next<int (*)(const char*, const char*)>("link");
    if (!may_write("link", AT_FDCWD, from) || !may_write("link", AT_FDCWD, to)) return -1;
    return real(from, to);
}

int linkat(int fromfd, const char* from, int tofd, const char* to, int flags) {
    static const auto real = next<int (*)(int, const char*, int, const char*, int)>("linkat");
    if (!may_write("linkat", fromfd, from) || !may_write("linkat", tofd, to)) return -1;
    return real(fromfd, from, tofd, to, flags);
}

// a link inside the folder could point anywhere: while confined, links are refused everywhere
int symlink(const char* target, const char* path) {
    static const auto real = next<int (*)(const char*, const char*)>("symlink");
    if (gaitlab::fuzz::active.load()) {
        may_write("symlink", AT_FDCWD, "/");
        return -1;
    }
    return real(target, path);
}

int symlinkat(const char* target, int dirfd, const char* path) {
    static const auto real = next<int (*)(const char*, int, const char*)>("symlinkat");
    if (gaitlab::fuzz::active.load()) {
        may_write("symlinkat", AT_FDCWD, "/");
        return -1;
    }
    return real(target, dirfd, path);
}

int chmod(const char* path, mode_t mode) {
    static const auto real = next<int (*)(const char*, mode_t)>("chmod");
    if (!may_write("chmod", AT_FDCWD, path)) return -1;
    return real(path, mode);
}

int fchmodat(int dirfd, const char* path, mode_t mode, int flags) {
    static const auto real = next<int (*)(int, const char*, mode_t, int)>("fchmodat");
    if (!may_write("fchmodat", dirfd, path)) return -1;
    return real(dirfd, path, mode, flags);
}

}  // extern "C"
