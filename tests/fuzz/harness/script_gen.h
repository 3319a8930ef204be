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
    /// true when generated: every path it names is relative and stays inside its folder, so a
    /// write outside the folder is a finding (a hand-written or mutated script may name any).
    bool generated = false;
};

/// The script input `data` stands for: the input itself when it starts with "--" (a Lua
/// comment: hand-written scripts of the corpus start with one), else generate_script(data).
Script script_for_input(const std::uint8_t* data, std::size_t size);

/// A script generated from `data`: each byte read chooses a production or a constant, and a
/// missing byte reads as 0, so every input gives a script, and similar inputs similar scripts.
std::string generate_script(const std::uint8_t* data, std::size_t size);

}  // namespace gaitlab::fuzz
