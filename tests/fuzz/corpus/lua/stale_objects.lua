-- objects used after what they belong to is gone, and shared between worlds and simulations
local robot = gaitlab.robot.chain{ name = "r", modules = 3 }
local w1, w2 = gaitlab.world{}, gaitlab.world{}
w1:add(robot)
print(pcall(w2.add, w2, robot))
print(pcall(w1.add, w1, robot))
local group = robot:group("all")
local ctl = group:drive(gaitlab.controllers.sine{})
local s1 = gaitlab.simulation{ world = w1 }
print(pcall(gaitlab.simulation, { world = w1 }))
s1:step(20)
print(robot:position(), robot:joints()[1].angle, ctl.amplitude)
s1 = nil
collectgarbage()
print(pcall(robot.position, robot))
print(pcall(robot.joints, robot))
local s2 = gaitlab.simulation{ world = w1 }
s2:step(10)
s2 = nil
w1 = nil
collectgarbage()
print(pcall(robot.position, robot))
print(pcall(group.drive, group, gaitlab.controllers.offset{}))
print(#robot:bodies(), ctl:values().time, ctl.failed)
local sensor = robot:sensor{ kind = "position" }
print(pcall(sensor.read, sensor))
local old = gaitlab.simulation{ world = w2 }
w2:add(gaitlab.robot.chain{ modules = 2 })
old:step(5)
print(tostring(old), tostring(w2))
