-- a world with robots and objects saved as an environment file and read back
local world = gaitlab.world{ floor = { friction = 0.7 } }
world:box{ size = { 0.1, 0.1, 0.1 }, mass = 0.2, position = { 1, 0, 0.05 } }
world:ramp{ slope = 10 }
local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
world:add(robot, { x = 0.5, yaw = 30 })
assert(world:save("w.environment.xml"))
local back = assert(gaitlab.world.load("w.environment.xml"))
print(back)
local again = gaitlab.robot.chain{ name = "snake", modules = 3 }
back:add(again)
gaitlab.simulation{ world = back }:step(5)
print(again:position())
