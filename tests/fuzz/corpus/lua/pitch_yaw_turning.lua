-- a pitch-yaw snake: a sine on the pitch joints, an offset bending the yaw joints, changed online
local robot = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-yaw" }
local world = gaitlab.world{ floor = { friction = 0.8 }, gravity = { 0, 0, -9.81 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local turn = robot:group("yaw"):drive(gaitlab.controllers.offset{ angle = 20 })
local sim = gaitlab.simulation{ world = world, control_every = 10 }
sim:run(0.5)
turn.angle = -20
sim:run(0.5)
local d = robot:displacement()
print(d.x, d.y, d:norm(), #robot, #robot:group("yaw"), #robot:group("all"))
