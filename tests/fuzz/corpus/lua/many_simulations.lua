-- many simulations of one world, reset, saved and dropped; the robot follows the newest
local robot = gaitlab.robot.chain{ name = "r", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local sims = {}
for i = 1, 8 do
  sims[i] = gaitlab.simulation{ world = world, dt = 0.001 * i, seed = i, record = i % 2 == 0 and ("runs/m" .. i) or false }
  sims[i]:step(10)
end
for i = 1, 8, 2 do sims[i]:reset() sims[i] = nil end
collectgarbage()
print(robot:position(), tostring(sims[2]))
for i = 2, 8, 2 do sims[i]:step(5) print(sims[i].time, sims[i].ticks, sims[i].record_dir) end
