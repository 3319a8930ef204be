-- The viewer's console test opens the console on this: a snake and its simulation, not run.
robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-pitch" }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1, phase = 120 })
sim = gaitlab.simulation{ world = world }
