-- A recorded simulation, then Lua code that never ends and swallows its errors (for the signal
-- tests): says "busy" on stderr once it spins.
local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
local world = gaitlab.world()
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = { flush_seconds = 60 } }
sim:run(0.5)
io.stderr:write("busy\n")
while true do
  pcall(function() sim:run(0.001) end)
end
