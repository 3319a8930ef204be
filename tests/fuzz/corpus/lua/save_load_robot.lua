-- a robot saved and loaded back, as gaitlab XML and as URDF
local robot = gaitlab.robot.chain{ name = "snake", modules = 5, connection = "pitch-yaw", module = "cube" }
robot:sensor{ kind = "imu", module = 3 }
assert(robot:save("snake.robot.xml"))
local copy = assert(gaitlab.robot.load("snake.robot.xml"))
print(copy.name, #copy, #copy:sensors())
assert(robot:save_urdf("snake.urdf"))
local urdf = assert(gaitlab.robot.load_urdf("snake.urdf"))
print(urdf.name, #urdf)
local worm = assert(gaitlab.robot.load_urdf("robots/inchworm.urdf"))
print(worm.name, #worm, #worm:bodies())
print(gaitlab.robot.load("missing.xml"))
print(gaitlab.robot.load("snake.urdf"))
print(gaitlab.robot.load_urdf("snake.robot.xml"))
print(robot:save("no/such/folder/x.xml"))
print(robot:save(""))
