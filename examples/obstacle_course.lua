-- An obstacle course built object by object from the world library (docs/worlds.md): walls
-- along a corridor, a log to climb over, two low steps, a patch of rubble. Every object takes a
-- position (m), a yaw (degrees) and a friction in [0, 1]; sizes are in m.
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:wall{ length = 3, height = 0.1, thickness = 0.02, position = { 1.2, 0.25, 0 } }
world:wall{ length = 3, height = 0.1, thickness = 0.02, position = { 1.2, -0.25, 0 } }
world:cylinder{ radius = 0.01, length = 0.45, lying = true, yaw = 90, position = { 0.75, 0, 0.01 } }
world:stairs{ steps = 2, step_height = 0.01, step_depth = 0.3, width = 0.45, landing = 0.2,
              position = { 1.1, 0, 0 } }
world:rubble{ length = 0.6, width = 0.45, count = 40, min_height = 0.003, max_height = 0.01,
              seed = 3, position = { 2.2, 0, 0 } }
world:box{ size = { 0.05, 0.05, 0.05 }, mass = 0.05, position = { 2.8, 0, 0.025 } }  -- pushable

local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = -120 })
print(world)

local sim = gaitlab.simulation{ world = world }
for t = 10, 60, 10 do
  sim:run(10)
  local p = robot:position()
  print(string.format("t = %2d s: centre of mass at x %.3f, y %+.3f, z %.3f m", t, p.x, p.y, p.z))
end
