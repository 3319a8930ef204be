-- sensors attached while the simulation runs read at once; sensors of a robot in no simulation
local robot = gaitlab.robot.chain{ modules = 3 }
local lone = robot:sensor{ kind = "position" }
print(pcall(lone.read, lone))
local world = gaitlab.world{}
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = { dir = "runs/s", series = { "sensor" } } }
sim:step(10)
local late = robot:sensor{ kind = "imu", module = 2 }
print(late:read().az)
sim:step(10)
late:off()
sim:reset()
print(late:read(), lone:read().z)
sim:record(false)
print(#gaitlab.data.open("runs/s"):series())
