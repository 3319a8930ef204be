-- What `require "gaitlab"` does to the interpreter that loads it (docs/embedding.md): run by
-- lua5.4 with a strict _G (every global read or written through _G's metamethods fails unless
-- declared), as strict.lua gives it.
local declared = { gaitlab = true }
local print, error, rawget, tostring = print, error, rawget, tostring
local original = { print = print, exit = os.exit, find = string.find, xpcall = xpcall,
                   resume = coroutine.resume, pairs = pairs, sort = table.sort }
setmetatable(_G, {
  __index = function(_, k) if not declared[k] then error("undefined global " .. tostring(k), 2) end end,
  __newindex = function(_, k) error("new global " .. tostring(k), 2) end,
})
local gaitlab = require "gaitlab"
print("version", type(gaitlab.version))
print("no global", rawget(_G, "gaitlab") == nil)
print("same table", require "gaitlab" == gaitlab)
package.loaded.gaitlab = nil
print("opened again: same table", require "gaitlab" == gaitlab)
print("print and os.exit are the interpreter's", print == original.print, os.exit == original.exit)
print("guarded: xpcall, coroutine.resume, string.find", xpcall ~= original.xpcall,
      coroutine.resume ~= original.resume, string.find ~= original.find)
print("string.find still finds", ("gaitlab"):find("lab"))
print("pairs and table.sort are the interpreter's", pairs == original.pairs,
      table.sort == original.sort)
-- a sandboxed controller file gets gaitlab's fixed order all the same
local file = io.open("order.lua", "w")
file:write([[
local t, seen = {}, {}
for i = 1, 50 do t["k" .. i] = i end
for k in pairs(t) do seen[#seen + 1] = k end
local tied = { { 1, "a" }, { 0, "b" }, { 1, "c" }, { 0, "d" } }
table.sort(tied, function(x, y) return x[1] < y[1] end)
error(table.concat(seen, ",", 1, 3) .. " " .. tied[1][2] .. tied[2][2] .. tied[3][2] .. tied[4][2], 0)
]])
file:close()
print("a sandbox's order", select(2, pcall(gaitlab.controller.load, "order.lua")))
-- no optimizer in an interpreter's state: gaitlab.optimize says where there is one
print("optimize", select(2, pcall(function() return gaitlab.optimize{ spec = "spec.lua" } end)))
-- a recording asked for: runs/defaults-<time>/, closed as finished when lua5.4 closes the state
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world()
world:add(robot)
local sim = gaitlab.simulation{ world = world }
print("records only when asked", sim.record_dir == nil)
sim:record(true)
sim:run(0.05)
print("record_dir", (sim.record_dir:gsub("%d", "N")))
