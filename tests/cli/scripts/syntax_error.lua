-- a script that does not parse: line 3
local robot = gaitlab.robot.chain{ modules = 4 }
local world = gaitlab.world{ floor = { friction = 0.8 } end
