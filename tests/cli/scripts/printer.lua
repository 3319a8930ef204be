-- A recorded simulation that prints a line every control step (for the broken pipe tests).
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world()
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = { flush_seconds = 0.2 } }
for _ = 1, 100000 do
  sim:run(0.03)
  print(string.format("%.2f", sim.time))
end
