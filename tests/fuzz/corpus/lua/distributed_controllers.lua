-- the remaining built-in controllers on one long robot, reset in between
local robot = gaitlab.robot.chain{ name = "long", modules = 10, connection = "pitch-yaw" }
local world = gaitlab.worlds.flat()
world:add(robot)
local a = robot:group("pitch"):drive(gaitlab.controllers.distributed{})
local b = robot:group("yaw"):drive(gaitlab.controllers.hindmarsh_rose{})
local sim = gaitlab.simulation{ world = world, control_every = 20 }
sim:step(100)
for k, v in pairs(a:params()) do print(k, v.value, v.default, v.min, v.max, v.unit) end
for k, v in pairs(b:values()) do print(k, v[1]) end
sim:reset()
sim:step(100)
