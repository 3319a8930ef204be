-- The viewer's tests watch this: a pitch-pitch snake with a sine wave and an IMU on its head,
-- a ramp, stairs, a static box and a box it can push, for arg[1] simulated seconds (default 4).
local robot = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:ramp{ slope = 10, length = 0.4, width = 0.4, position = { 0.2, 0.5, 0 } }
world:stairs{ steps = 3, step_height = 0.02, step_depth = 0.1, width = 0.4,
              position = { -0.5, 0.5, 0 } }
world:box{ size = { 0.1, 0.1, 0.05 }, position = { 0.3, -0.3, 0.025 } }
world:box{ size = { 0.05, 0.05, 0.05 }, position = { 0.6, -0.3, 0.025 }, mass = 0.05 }
robot:sensor{ kind = "imu", module = 6 }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1, phase = 120 })
local sim = gaitlab.simulation{ world = world }
sim:run(tonumber(arg[1]) or 4)
print(string.format("moved %.3f m", robot:displacement():norm()))
