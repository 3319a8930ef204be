-- a step that replaces its self table's metatable: the method box is collected while the
-- controller still points at it, and the next bind (sim:reset) writes into freed memory
local Drop = gaitlab.controller{ name = "drop", step = function(self) setmetatable(self, nil) end }
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(Drop())
local sim = gaitlab.simulation{ world = world }
sim:step(30)
collectgarbage()
collectgarbage()
sim:reset()
