-- a snake on the floor, driven by a sine: the README's first script, run for a short time
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local sim = gaitlab.simulation{ world = world, dt = 0.001, control_every = 30 }
sim:run(1)
local d = robot:displacement()
print(string.format("moved %.3f m (x %.3f, y %.3f)", d:norm(), d.x, d.y))
