#include "fixed_order.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <vector>

#include "guard.h"
#include "lua_util.h"

// Written here because no library offers them: they are the standard `pairs` with one sort
// added, and a merge sort over Lua values (fixed_order.h says why both are needed).

namespace gaitlab::scripting {

namespace {

// One key of the table being visited, as the sort compares it.
struct Key {
    int rank;       // 0 numbers, 1 strings, 2 booleans, 3 gaitlab's userdata, 4 everything else
    bool integer;   // numbers: an integer subtype; gaitlab's userdata: true
    lua_Integer i;  // numbers: the integer; gaitlab's userdata: their number (number_object)
    lua_Number x;   // numbers: the value as a float
    const char* s;  // strings (anchored by the table that holds them), booleans: "" or "t"
    std::size_t len;
    lua_Integer index;  // where Lua's own traversal put it (keeps ties in a stable order)
};

// i < x exactly, and x < i (as Lua's < compares an integer and a float): converted to a float,
// an integer beyond 2^53 is rounded, and math.maxinteger - 1 tied with the float 2^63. Only
// such floats (beyond the integers' range) and fractions come here: Lua turns a float key with
// an integer value into that integer
bool int_below_float(lua_Integer i, lua_Number x) {
    if (x >= 0x1p63) return true;
    if (x <= -0x1p63) return false;
    return i < static_cast<lua_Integer>(std::ceil(x));
}

bool float_below_int(lua_Number x, lua_Integer i) {
    if (x >= 0x1p63) return false;
    if (x < -0x1p63) return true;
    return static_cast<lua_Integer>(std::floor(x)) < i;
}

// small and without a switch, so that the sort inlines it (it runs n log n times)
bool before(const Key& a, const Key& b) {
    if (a.rank != b.rank) return a.rank < b.rank;
    if (a.rank == 1 || a.rank == 2) {
        const int c = std::memcmp(a.s, b.s, std::min(a.len, b.len));
        return c != 0 ? c < 0 : a.len < b.len;
    }
    // numbers; gaitlab's userdata by their (integer) number; other keys all 0, so they keep
    // Lua's order, which is by address
    if (a.integer && b.integer) return a.i < b.i;
    if (a.integer) return int_below_float(a.i, b.x);
    if (b.integer) return float_below_int(a.x, b.i);
    return a.x < b.x;
}

// the key at `index`; `made` is the kMadeKey table (absolute), 0 if there is none
Key key_at(lua_State* L, int index, int made, lua_Integer position) {
    Key k{4, false, 0, 0, "", 0, position};
    switch (lua_type(L, index)) {
        case LUA_TNUMBER:
            k.rank = 0;
            k.integer = lua_isinteger(L, index);
            k.i = k.integer ? lua_tointeger(L, index) : 0;
            k.x = lua_tonumber(L, index);
            break;
        case LUA_TSTRING:
            k.rank = 1;
            k.s = lua_tolstring(L, index, &k.len);  // a string key: no conversion, no allocation
            break;
        case LUA_TBOOLEAN:
            k.rank = 2;
            k.s = lua_toboolean(L, index) ? "t" : "";
            k.len = std::strlen(k.s);
            break;
        case LUA_TUSERDATA:
            if (made != 0) {
                k.i = object_number(L, index, made);
                if (k.i > 0) {
                    k.rank = 3;
                    k.integer = true;
                }
            }
            break;
        default:
            break;
    }
    return k;
}

// the iterator: upvalue 1 the table, 2 its keys in order, 3 the position of the last key given;
// keys whose value became nil since (a loop may clear fields it visits) are passed over
int ordered_next(lua_State* L) {
    const int table = lua_upvalueindex(1), keys = lua_upvalueindex(2), at = lua_upvalueindex(3);
    lua_Integer position = lua_tointeger(L, at);
    const auto count = static_cast<lua_Integer>(lua_rawlen(L, keys));
    while (position < count) {
        ++position;
        lua_rawgeti(L, keys, position);
        lua_pushvalue(L, -1);
        if (lua_rawget(L, table) != LUA_TNIL) {
            lua_pushinteger(L, position);
            lua_replace(L, at);
            return 2;
        }
        lua_pop(L, 2);
    }
    lua_pushinteger(L, position);
    lua_replace(L, at);
    lua_pushnil(L);
    return 1;
}

// pushes the keys of the table at `table` (absolute) as an array, in the order of `before`
void push_ordered_keys(lua_State* L, int table) {
    lua_Integer count = 0;
    lua_pushnil(L);
    while (lua_next(L, table) != 0) {
        lua_pop(L, 1);
        ++count;
    }
    // both arrays made before the sort, so nothing allocates in Lua while its vector lives
    lua_createtable(L, static_cast<int>(count), 0);  // Lua's order
    const int found = lua_gettop(L);
    lua_createtable(L, static_cast<int>(count), 0);  // the sorted order
    const int sorted = lua_gettop(L);
    // the numbers of gaitlab's userdata (none made yet: no table)
    int made = 0;
    if (lua_getfield(L, LUA_REGISTRYINDEX, kMadeKey) == LUA_TTABLE) {
        made = lua_gettop(L);
    } else {
        lua_pop(L, 1);
    }
    lua_Integer n = 0;
    lua_pushnil(L);
    while (lua_next(L, table) != 0) {
        lua_pop(L, 1);
        lua_pushvalue(L, -1);
        lua_rawseti(L, found, ++n);
    }
    {
        std::vector<Key> order;
        order.reserve(static_cast<std::size_t>(n));
        for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, found, i);
            order.push_back(key_at(L, -1, made, i));
            lua_pop(L, 1);
        }
        std::stable_sort(order.begin(), order.end(), before);
        for (lua_Integer i = 1; i <= n; ++i) {
            lua_rawgeti(L, found, order[static_cast<std::size_t>(i - 1)].index);
            lua_rawseti(L, sorted, i);
        }
    }
    if (made != 0) lua_remove(L, made);
    lua_remove(L, found);
}

}  // namespace

// pairs(t): as Lua's (a __pairs metamethod decides if there is one), but a table's keys come
// in a fixed order: numbers ascending, then strings in byte order, then false and true, then
// gaitlab's userdata in the order they were made, then other keys in Lua's order
int fixed_order_pairs(lua_State* L) {
    luaL_checkany(L, 1);
    if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {
        lua_pushvalue(L, 1);
        lua_call(L, 1, 3);
        return 3;
    }
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_Integer keys = 0;
    const int results = protect(L, [&] {
        lua_settop(L, 1);
        lua_pushvalue(L, 1);
        push_ordered_keys(L, 1);
        keys = static_cast<lua_Integer>(lua_rawlen(L, -1));
        lua_pushinteger(L, 0);
        lua_pushcclosure(L, ordered_next, 3);
        lua_pushvalue(L, 1);
        lua_pushnil(L);
        return 3;
    });
    // the sort ran in C, where a controller's instruction budget counts nothing: its n log n
    // comparisons are charged to the budget here (a step that sorts a big table over and
    // over stops as a loop would)
    if (keys > 1) {
        long long depth = 1;
        while ((lua_Integer{1} << depth) < keys)
            ++depth;
        Guard::charge(L, keys * depth);
    }
    return results;
}

// table.sort(list [, comp]): as Lua's (the elements read and written with lua_geti and
// lua_seti, `comp` or `<` comparing), but a bottom-up merge sort, which never consults the
// clock and keeps equal elements in their order. Plain C: a comparison may raise a Lua error,
// so nothing with a destructor lives here.
int stable_sort(lua_State* L) {
    luaL_checktype(L, 1, LUA_TTABLE);
    const lua_Integer n = luaL_len(L, 1);
    luaL_argcheck(L, n < INT_MAX, 1, "array too big");
    const bool has_comp = !lua_isnoneornil(L, 2);
    if (has_comp) luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_settop(L, 2);
    if (n < 2) return 0;
    lua_createtable(L, static_cast<int>(n), 0);  // 3: the runs being merged
    lua_createtable(L, static_cast<int>(n), 0);  // 4: where they are merged to
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_geti(L, 1, i);
        lua_rawseti(L, 3, i);
    }
    // less(b, a) for the values at the stack's top two places (a below b); pops them
    auto less = [L, has_comp]() {
        bool result;
        if (has_comp) {
            lua_pushvalue(L, 2);
            lua_rotate(L, -3, 1);  // comp a b
            lua_rotate(L, -2, 1);  // comp b a
            lua_call(L, 2, 1);
            result = lua_toboolean(L, -1);
            lua_pop(L, 1);
        } else {
            result = lua_compare(L, -1, -2, LUA_OPLT);
            lua_pop(L, 2);
        }
        return result;
    };
    int from = 3, to = 4;
    for (lua_Integer width = 1; width < n; width *= 2) {
        for (lua_Integer lo = 1; lo <= n; lo += 2 * width) {
            const lua_Integer mid = std::min(lo + width, n + 1),
                              hi = std::min(lo + 2 * width, n + 1);
            lua_Integer a = lo, b = mid, out = lo;
            while (a < mid && b < hi) {
                lua_rawgeti(L, from, a);
                lua_rawgeti(L, from, b);
                const bool take_b = less();  // the right run's element only if strictly less
                lua_rawgeti(L, from, take_b ? b++ : a++);
                lua_rawseti(L, to, out++);
            }
            while (a < mid) {
                lua_rawgeti(L, from, a++);
                lua_rawseti(L, to, out++);
            }
            while (b < hi) {
                lua_rawgeti(L, from, b++);
                lua_rawseti(L, to, out++);
            }
        }
        std::swap(from, to);
    }
    for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, from, i);
        lua_seti(L, 1, i);
    }
    return 0;
}

void open_fixed_order(lua_State* L) {
    lua_pushcfunction(L, fixed_order_pairs);
    lua_setglobal(L, "pairs");
    lua_getglobal(L, "table");
    lua_pushcfunction(L, stable_sort);
    lua_setfield(L, -2, "sort");
    lua_pop(L, 1);
}

}  // namespace gaitlab::scripting
