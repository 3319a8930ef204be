// The Lua fuzzer's inputs: a fuzz input is either a hand-written script, run as it is, or the
// choices of a grammar of the public gaitlab Lua API (docs/lua-api.md) with hostile arguments,
// from which a script is generated.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace gaitlab::fuzz {

/// What one fuzz input runs.
struct Script {
    std::string code;
    /// Every path the script gives stays inside its folder, so a write outside the folder is a
    /// finding (gaitlab made a path of a name, say); the script may call __fuzz_finding(message)
    /// to report its own checks. Generated scripts are strict, and so are hand-written ones
    /// whose first line starts with "-- strict" where `strict_marks` is set: lua_fuzz_replay
    /// sets it, lua_fuzz does not (libFuzzer's mutations of a script keep its first line and
    /// may name any path: a mutated script's writes outside its folder are only refused).
    bool strict = false;
};

/// The script input `data` stands for: the input itself when it starts with "--" (a Lua
/// comment: hand-written scripts of the corpus start with one), else generate_script(data).
Script script_for_input(const std::uint8_t* data, std::size_t size, bool strict_marks = false);

/// A script generated from `data`: each byte read chooses a production or a constant, and a
/// missing byte reads as 0, so every input gives a script, and similar inputs similar scripts.
std::string generate_script(const std::uint8_t* data, std::size_t size);

}  // namespace gaitlab::fuzz
