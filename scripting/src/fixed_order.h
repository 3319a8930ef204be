// A host's `pairs` and `table.sort`, which give the same order in every process. Lua 5.4 seeds
// its string hashes from the clock and from addresses, so its own `next` visits string keys in
// a different order in each run, and its `table.sort` picks pivots from the clock, so elements
// that compare equal end in a different order from run to run. Either breaks the promise that
// the same script, seed and binary give the same trajectory as soon as a script builds robots,
// adds numbers or picks the best candidates in that order. Lua's order of userdata keys is by
// address, which changes from run to run too: gaitlab's handles (robots, sensors, controllers
// ... as keys) come in the order they were made, which the script decides.
#pragma once

#include <lua.hpp>

namespace gaitlab::scripting {

/// Sets, in L's state, the global `pairs` to one that visits a table's keys in an order of
/// their values (numbers ascending, then strings in byte order, then false and true, then
/// gaitlab's userdata in the order the state made them (new_object), then other keys in Lua's
/// order), and `table.sort` to a stable merge sort (equal elements keep their order).
void open_fixed_order(lua_State* L);

/// The two functions themselves: every sandbox gets them, also in an interpreter that did
/// `require "gaitlab"` (whose own globals gaitlab leaves alone).
int fixed_order_pairs(lua_State* L);
int stable_sort(lua_State* L);

}  // namespace gaitlab::scripting
