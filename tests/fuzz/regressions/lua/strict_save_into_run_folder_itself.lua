-- strict: "." and "" name the run folder itself, which is inside it (the harness once took the
-- rename onto the folder, which fails anyway, for a write outside it)
local world = gaitlab.world{}
print(world:save("."))
print(world:save(""))
print(world:save("./"))
local robot = gaitlab.robot.chain{ modules = 2 }
print(robot:save("."))
print(robot:save_urdf("./"))
world:add(robot)
print(gaitlab.simulation{ world = world }:save("."))
