-- Joint feedback: ask for a gait faster than the servos can follow and let the controller of
-- examples/controllers/adaptive_sine.lua slow it down until the joints swing as wide as asked.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
local Adaptive = gaitlab.controller.load("controllers/adaptive_sine.lua")
local ctl = robot:group("pitch"):drive(Adaptive{ amplitude = 60, frequency = 3, phase = 120 })
local sim = gaitlab.simulation{ world = world }
for _ = 1, 4 do
  sim:run(5)
  local v = ctl:values()
  print(string.format("t = %4.1f s: running at %.2f Hz, joint 1 swings %.0f deg (asked 60)",
    sim.time, v.running[1], v.reached[1]))
end
local d = robot:displacement()
print(string.format("moved %.3f m (x %.3f, y %.3f)", d:norm(), d.x, d.y))
