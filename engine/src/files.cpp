#include "gaitlab/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "data/files.h"

namespace gaitlab {

using data::reason;
using data::write_all;

void write_file_atomic(const std::string& path, std::string_view text) {
    const std::string tmp = path + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
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
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw IoError(fmt::format("cannot write {}: {}", path, reason(e)));
    }
}

}  // namespace gaitlab
