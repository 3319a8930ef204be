-- The viewer's simulation chooser watches this: a pitch-pitch snake runs 0.3 s, a copy of it is
-- made then (its amplitude set to 30), the original runs 0.3 s more, and a second world with a
-- two-module worm gets a simulation of its own. Three simulations: 1 the original, 2 its copy,
-- 3 the worm.
local robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 1, phase = 120 })
local sim = gaitlab.simulation{ world = world }
sim:run(0.3)
local copy = sim:clone()
copy:robot("snake"):controllers()[1].amplitude = 30
sim:run(0.3)
local worm = gaitlab.robot.chain{ name = "worm", modules = 2 }
local other = gaitlab.world{}
other:add(worm)
worm:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 10 })
gaitlab.simulation{ world = other }
print(string.format("original at %.1f s, copy at %.1f s", sim.time, copy.time))
