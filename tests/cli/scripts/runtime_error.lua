-- a script that fails while it runs: line 4 calls a field that does not exist
local robot = gaitlab.robot.chain{ modules = 4 }
local world = gaitlab.world()
world.populate(robot)
