-- ends with os.exit after a recorded simulation: the run folder is closed first
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world()
world:add(robot)
gaitlab.simulation{ world = world, record = { flush_seconds = 60 } }:run(1)
print("leaving")
os.exit(tonumber(arg[1]) or 0)
