/* gaitlab.so: what `require "gaitlab"` loads from LUA_CPATH (docs/embedding.md).
 *
 * gaitlab itself (gaitlab/core.so, next to this file) uses the Lua 5.4 API, which an
 * interpreter for another Lua does not have: loaded into lua5.3, lua5.1 or LuaJIT it would fail
 * in the dynamic linker ("undefined symbol: lua_newuserdatauv") or, worse, find a function of
 * the same name that does something else. So this file uses only what every Lua since 5.1 and
 * LuaJIT provide (luaL_error and the C library): it checks that the Lua API of the process is
 * 5.4's, and only then loads gaitlab/core.so and hands over to its luaopen_gaitlab_core.
 *
 * Neither file links a Lua library: the interpreter provides the API (linking liblua5.4 would
 * put a second Lua core in lua5.4, whose objects the first must never see). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include <lauxlib.h>
#include <lua.h>

/* which Lua provides the API the interpreter runs (whatever this file's luaL_error resolved
 * to): "LuaJIT", "Lua 5.3.6" ..., for the message */
static void name_lua(char* out, size_t size) {
    const char* ident;
    const char* at;
    size_t n = 0;
    if (dlsym(RTLD_DEFAULT, "luaJIT_setmode")) {
        snprintf(out, size, "LuaJIT");
        return;
    }
    /* every Lua from 5.1 on has lua_ident: "$LuaVersion: Lua 5.3.6 ..." or "$Lua: Lua 5.1.5 ..." */
    ident = (const char*)dlsym(RTLD_DEFAULT, "lua_ident");
    at = ident ? strstr(ident, "Lua 5.") : NULL;
    if (at) {
        while (at[n] && at[n] != ' ' && n < 8)
            ++n; /* "Lua", then up to "5.x.y" */
        if (at[n] == ' ') {
            ++n;
            while (at[n] && at[n] != ' ' && n < 16)
                ++n;
        }
        snprintf(out, size, "%.*s", (int)n, at);
        return;
    }
    snprintf(out, size, "not Lua 5.4");
}

/* whether the object that provides luaL_error (the Lua the interpreter runs) is a Lua 5.4:
 * it must also provide lua_newuserdatauv, new in 5.4 */
static int is_lua54(void) {
    Dl_info api, uv;
    void* newuserdatauv = dlsym(RTLD_DEFAULT, "lua_newuserdatauv");
    if (!newuserdatauv || !dladdr((void*)&luaL_error, &api) || !dladdr(newuserdatauv, &uv)) {
        return 0;
    }
    return api.dli_fbase == uv.dli_fbase;
}

__attribute__((visibility("default"))) int luaopen_gaitlab(lua_State* L) {
    typedef int (*open_fn)(lua_State*);
    char path[4096];
    char lua[32];
    Dl_info self;
    const char* slash;
    int n;
    void* core;
    open_fn open;
    if (!is_lua54()) {
        name_lua(lua, sizeof lua);
        return luaL_error(L,
                          "gaitlab needs Lua 5.4, and this interpreter runs %s: run the script "
                          "with lua5.4",
                          lua);
    }
    /* gaitlab/core.so next to this file, as the interpreter found it */
    if (!dladdr((void*)&luaopen_gaitlab, &self) || !self.dli_fname) {
        return luaL_error(L, "gaitlab: cannot tell where gaitlab.so is");
    }
    slash = strrchr(self.dli_fname, '/');
    n = slash ? snprintf(path, sizeof path, "%.*s/gaitlab/core.so", (int)(slash - self.dli_fname),
                         self.dli_fname)
              : snprintf(path, sizeof path, "./gaitlab/core.so");
    if (n < 0 || (size_t)n >= sizeof path) {
        return luaL_error(L, "gaitlab: the path of gaitlab.so is too long");
    }
    /* RTLD_LOCAL: nothing of gaitlab's (its C++ libraries' symbols) joins the interpreter's */
    core = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!core) return luaL_error(L, "gaitlab: cannot load %s: %s", path, dlerror());
    open = (open_fn)dlsym(core, "luaopen_gaitlab_core");
    if (!open) return luaL_error(L, "gaitlab: %s has no luaopen_gaitlab_core", path);
    return open(L); /* core.so stays loaded for the life of the process */
}
