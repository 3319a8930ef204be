-- a simulation saved with its parts, loaded back and run: the copy follows the same trajectory
local robot = gaitlab.robot.chain{ name = "snake", modules = 4, connection = "pitch-yaw" }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
local yaw = robot:group("yaw"):drive(gaitlab.controllers.phase_chain{ seed = 3 })
yaw.coupling = 5
local sim = gaitlab.simulation{ world = world, control_every = 10, seed = 4, solver_iterations = 15 }
print(sim:save("saved/roll.xml"))
assert(sim:save("roll.xml", { duration = 0.1 }))
sim:run(0.1)
local copy, setup = assert(gaitlab.simulation.load("roll.xml"))
print(setup.name, setup.duration, setup.world, setup.record.dir, setup.record.every)
copy:run(setup.duration)
print(robot:position() == setup.robots.snake:position())
for name, list in pairs(setup.controllers) do print(name, #list, list[1].name) end
local walk, s2 = gaitlab.simulation.load("walk.xml")
if walk then walk:step(50) print(s2.name) else print(s2) end
print(gaitlab.simulation.load("missing.xml"))
