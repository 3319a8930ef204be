-- recording started and stopped while the simulation runs, twice, and into a used folder
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = false }
sim:step(10)
print(sim:record("runs/late"))
print(pcall(sim.record, sim, "runs/other"))
sim:step(10)
sim:record(false)
sim:record(false)
print(sim.record_dir)
print(pcall(sim.record, sim, "runs/late"))
print(pcall(sim.record, sim, { dir = "runs/third", record_every = 0 }))
print(pcall(sim.record, sim, { dir = "runs/third", series = { "nothing*" } }))
print(pcall(sim.record, sim, ""))
print(pcall(sim.record, sim, true))
sim:step(5)
sim:flush()
