-- Climbing a ramp. gaitlab.worlds holds ready-made worlds (worlds/*.lua, see docs/worlds.md);
-- each returns the world and a start placement for the robot, here on the slope, head uphill.
-- A negative phase makes the body wave travel tail-wards, so the robot moves head first: up.
-- Try slope = 20, friction = 0.3, or another world: gaitlab.worlds.stairs{ step_height = 0.01 }.
local world, start = gaitlab.worlds.ramp{ slope = 10, friction = 0.8 }
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
world:add(robot, start)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = -120 })
local sim = gaitlab.simulation{ world = world }

local before = robot:position()
sim:run(20)
local after = robot:position()
print(string.format("in 20 s the snake climbed %.3f m along x and %.3f m up", after.x - before.x,
  after.z - before.z))
