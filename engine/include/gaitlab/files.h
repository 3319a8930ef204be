// Writing files so that a reader never sees half of one: configuration files, run metadata,
// controller templates.
#pragma once

#include <string>
#include <string_view>

#include "gaitlab/error.h"

namespace gaitlab {

/// Writes `text` to `path` atomically: into a temporary file in the same folder, flushed, then
/// renamed over `path`. On failure nothing at `path` changes and IoError names the path.
void write_file_atomic(const std::string& path, std::string_view text);

}  // namespace gaitlab
