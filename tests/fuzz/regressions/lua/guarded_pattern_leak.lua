-- a sandboxed controller file whose pattern is refused leaks the pattern's copy, every time
local f = assert(io.open("leak.lua", "w"))
f:write([[
return gaitlab.controller{
  name = "leak",
  step = function(self)
    for i = 1, 100 do pcall(string.find, string.rep("a", 40), ".-.-.-.-.-.-.-.-.-.-b") end
  end,
}
]])
f:close()
local robot = gaitlab.robot.chain{ modules = 1 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(gaitlab.controller.load("leak.lua")())
gaitlab.simulation{ world = world }:step(300)
