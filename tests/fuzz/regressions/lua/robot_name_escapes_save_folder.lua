-- strict: a robot's name becomes part of the file names sim:save writes, unchecked: a name
-- with "/" and ".." puts the robot file outside the folder of the simulation file
local robot = gaitlab.robot.chain{ name = "x/../../gaitlab_escape", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
-- a folder "sim.x" to go through (recording creates folders; so does any earlier save)
local sim = gaitlab.simulation{ world = world, record = "sim.x" }
sim:record(false)
print(sim:save("sim.xml"))
