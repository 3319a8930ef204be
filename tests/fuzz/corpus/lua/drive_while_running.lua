-- groups driven after the simulation was made, between runs; a controller drives one group only
local robot = gaitlab.robot.chain{ name = "r", modules = 4, connection = "pitch-yaw" }
local world = gaitlab.world{}
world:add(robot)
local pitch, yaw = robot:group("pitch"), robot:group("yaw")
local sim = gaitlab.simulation{ world = world, control_every = 5 }
sim:step(20)
local sine = pitch:drive(gaitlab.controllers.sine{ amplitude = 30 })
print(pcall(yaw.drive, yaw, sine))
sim:step(20)
yaw:drive(gaitlab.controllers.offset{ angle = 10 })
robot:group{ 1, 2 }:drive(gaitlab.controller.template("blank")())
sim:step(20)
sim:reset()
sim:step(20)
print(#robot:actuation(), sim.ticks)
