-- a misspelt key: line 2
local robot = gaitlab.robot.chain{ modules = 4, conection = "pitch-yaw" }
