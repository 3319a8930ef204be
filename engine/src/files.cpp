#include "gaitlab/files.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

namespace gaitlab {

void write_file_atomic(const std::string& path, std::string_view text) {
    // the temporary file sits next to the target so the rename stays within one file system
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw IoError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
    const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const int write_errno = errno;
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) {
        std::remove(tmp.c_str());
        throw IoError(
            fmt::format("cannot write {}: {}", path, std::strerror(written ? errno : write_errno)));
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw IoError(fmt::format("cannot write {}: {}", path, ec.message()));
    }
}

}  // namespace gaitlab
