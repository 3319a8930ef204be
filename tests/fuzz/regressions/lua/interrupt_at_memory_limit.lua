-- an interrupt that finds the Lua state at its memory limit: Guard::hook cannot push its message,
-- so the script fails with "not enough memory" instead of "interrupted (...)", and the message's
-- std::string is leaked (24 bytes). Under ASan the filling takes a few seconds: run with
-- GAITLAB_FUZZ_SECONDS=8 build-fuzz/tests/fuzz/lua_fuzz FILE
local keep
for size = 4096, 1, -1 do
  pcall(function()
    local piece = string.rep("m", size)
    while true do keep = { keep, piece .. #tostring(keep) } end
  end)
end
pcall(function() while true do keep = { keep } end end)
pcall(function() while true do keep = { keep, true } end end)
while true do end
