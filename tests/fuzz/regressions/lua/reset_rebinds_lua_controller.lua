-- sim:reset rebinds a Lua controller: its old self table is released before the old method box
-- is cleared, and a garbage collection in between frees the box that is then written
collectgarbage("incremental", 1, 1000)
local Wave = gaitlab.controller{ name = "wave", values = { "time" }, step = function(self) end }
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(Wave())
local sim = gaitlab.simulation{ world = world }
for _ = 1, 200 do sim:reset() end
