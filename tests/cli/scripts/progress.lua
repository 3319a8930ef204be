-- A run that takes about a second of wall time whatever the machine (for the progress line
-- tests): the controller spends about 4 ms of CPU per step, 200 steps. Prints one line of data.
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world()
world:add(robot)
robot:group("all"):drive(gaitlab.controller{ name = "slow",
  step = function(self)
    local t = os.clock() + 0.004
    while os.clock() < t do end
  end }())
local sim = gaitlab.simulation{ world = world }
sim:run(6)
print(string.format("done at t = %.1f", sim.time))
