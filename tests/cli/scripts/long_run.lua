-- A long recorded run (for the kill and full-disk tests): flushes every 0.2 s of wall time and,
-- unless arg[1] is "quiet", writes the simulated time to stderr after every 0.3 s of it.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8 }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local sim = gaitlab.simulation{ world = world, record = { flush_seconds = 0.2 } }
local quiet = arg[1] == "quiet"
for _ = 1, 100000 do
  sim:run(0.3)
  if not quiet then io.stderr:write(string.format("%.3f\n", sim.time)) end
end
