-- A snake driven by the Lua controller in controllers/my_sine.lua (paths resolve against this
-- script's folder). Edit the controller, run again: no compiling.
local MySine = gaitlab.controller.load("controllers/my_sine.lua")

local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
local ctl = robot:group("pitch"):drive(MySine{ amplitude = 30 })
local sim = gaitlab.simulation{ world = world }

sim:run(10)
ctl.amplitude = 45                                 -- online parameter change, range-checked
sim:run(10)
local d = robot:displacement()
print(string.format("my_sine: moved %.3f m (x %.3f, y %.3f) in %.0f s", d:norm(), d.x, d.y, sim.time))
