-- Every part of a simulation is a file: build one in Lua, save it, load it back and run it.
-- sim:save writes the simulation file and, next to it, the environment, each robot and each
-- robot's actuation (docs/formats.md). The copy runs exactly the same trajectory.
local folder = os.tmpname()
os.remove(folder)
assert(os.execute("mkdir -p " .. folder))

local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, phase = 120 })
local yaw = robot:group("yaw"):drive(gaitlab.controllers.sine{ amplitude = 20, phase = 120 })
yaw.phase0 = 90                                        -- changed online: saved as it is now
local sim = gaitlab.simulation{ world = world, control_every = 10 }
print("saved " .. assert(sim:save(folder .. "/roll.xml", { duration = 5 })))

sim:run(5)
local copy, setup = assert(gaitlab.simulation.load(folder .. "/roll.xml"))
copy:run(setup.duration)
local a, b = robot:position(), setup.robots.snake:position()
print(string.format("original at (%.4f, %.4f), copy at (%.4f, %.4f): %s", a.x, a.y, b.x, b.y,
  a == b and "identical" or "different"))
assert(a == b)
os.execute("rm -r " .. folder)
