-- Records a short run of a robot named arg[1] (names that would run commands if they reached a
-- shell or a gnuplot script as text).
local robot = gaitlab.robot.chain{ name = arg[1], modules = 2 }
local world = gaitlab.world()
world:add(robot)
gaitlab.simulation{ world = world }:run(0.1)
