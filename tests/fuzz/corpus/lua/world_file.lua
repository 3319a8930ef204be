-- a world file written by the script and loaded with gaitlab.world.load, good and broken ones
local f = assert(io.open("arena.lua", "w"))
f:write([[
return gaitlab.world.preset{
  name = "tiny",
  params = { friction = { 0.5, min = 0, max = 1 } },
  build = function(p) return gaitlab.world{ floor = { friction = p.friction } } end,
}
]])
f:close()
local Tiny = gaitlab.world.load("arena.lua")
local world = Tiny{ friction = 0.9 }
print(world)
local g = assert(io.open("broken.lua", "w"))
g:write("return 42")
g:close()
print(pcall(gaitlab.world.load, "broken.lua"))
print(pcall(gaitlab.world.load, "missing.lua"))
print(gaitlab.world.load("walk/flat.environment.xml"))
print(gaitlab.world.load("missing.xml"))
