-- A script that leaves a simulation playing: `gaitlab run` notes that playing is for the
-- console, and ends.
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world()
world:add(robot)
local sim = gaitlab.simulation{ world = world }
sim:play()
print(sim.playing)
