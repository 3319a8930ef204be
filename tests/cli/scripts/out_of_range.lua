-- an online parameter change out of range: line 7
local robot = gaitlab.robot.chain{ modules = 4 }
local world = gaitlab.world()
world:add(robot)
local ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
local sim = gaitlab.simulation{ world = world }
ctl.amplitude = 120
sim:run(1)
