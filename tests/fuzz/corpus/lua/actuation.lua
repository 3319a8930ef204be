-- a robot's actuation: read, saved, loaded and applied to another robot
local robot = gaitlab.robot.chain{ name = "a", modules = 4, connection = "pitch-yaw" }
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 25 })
robot:group{ 2, 4 }:drive(gaitlab.controllers.offset{ angle = 10 })
local act = robot:actuation()
print(#act, act, act:groups()[1].controller.builtin)
assert(act:save("a.actuation.xml"))
local back = assert(gaitlab.actuation.load("a.actuation.xml"))
local other = gaitlab.robot.chain{ name = "b", modules = 4, connection = "pitch-yaw" }
local ctls = other:actuate(back)
print(#ctls, ctls[1].amplitude)
local small = gaitlab.robot.chain{ name = "c", modules = 1 }
print(pcall(small.actuate, small, back))
local walk = gaitlab.actuation.load("walk/snake.actuation.xml")
print(walk and #walk)
print(gaitlab.actuation.load("missing.xml"))
