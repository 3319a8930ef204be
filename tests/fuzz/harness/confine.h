// Write confinement for the Lua fuzzer: while a fuzzed script runs, nothing in the process may
// create, change or delete a file outside the script's own folder. The C library's file
// functions (open, fopen, mkdir, rename, unlink ...) are interposed by definitions in this
// executable (Linux, glibc): reads pass, writes under the folder pass, and any other write fails
// with EACCES, which gaitlab sees as an ordinary I/O error. A fuzzed script can therefore not
// damage the machine, whatever path it gives, and a write that gaitlab sends outside the folder
// although the script named a path inside it (a name turned into a path, say) is caught.
#pragma once

#include <string>
#include <vector>

namespace gaitlab::fuzz {

/// From now on, writes outside `folder` (an absolute path without symbolic links) and the
/// folders given to allow_writes_in() fail.
void confine_writes(const std::string& folder);
/// Lets writes into `folder` (and below) pass even while confined: where the fuzzer itself
/// writes, crash reports and new corpus entries, when a script crashes it.
void allow_writes_in(const std::string& folder);
/// Lifts the confinement.
void release_writes();
/// The writes refused since the last confine_writes(), as "CALL PATH" lines.
std::vector<std::string> refused_writes();

}  // namespace gaitlab::fuzz
