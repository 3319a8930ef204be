-- a sensor on a module the robot does not have: line 3, before anything runs
local robot = gaitlab.robot.chain{ name = "snake", modules = 8 }
robot:sensor{ kind = "imu", module = 9 }
print("not reached")
