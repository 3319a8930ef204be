-- a Lua controller that fails in step, at line 5 of controllers/bad_step.lua
local Bad = gaitlab.controller.load("controllers/bad_step.lua")
local robot = gaitlab.robot.chain{ modules = 3 }
local world = gaitlab.world()
world:add(robot)
robot:group("all"):drive(Bad{})
local sim = gaitlab.simulation{ world = world }
sim:run(1)
