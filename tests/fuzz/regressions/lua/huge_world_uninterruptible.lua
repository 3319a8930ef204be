-- a world of a million stones: building its simulation cannot be interrupted
local w = gaitlab.world{}
for i = 1, 10 do w:rubble{ count = 100000, length = 50, width = 50, seed = i } end
w:add(gaitlab.robot.chain{ modules = 2 })
local t0 = os.clock()
local sim = gaitlab.simulation{ world = w }
print("sim", os.clock() - t0)
