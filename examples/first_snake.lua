-- examples/first_snake.lua: the README's main job
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)                                   -- lying on the floor along +x, head towards +x
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local sim = gaitlab.simulation{ world = world, dt = 0.001, control_every = 30 }
sim:run(20)                                        -- 20 simulated seconds
local d = robot:displacement()                     -- centre-of-mass displacement since start, metres
print(string.format("moved %.3f m (x %.3f, y %.3f)", d:norm(), d.x, d.y))
