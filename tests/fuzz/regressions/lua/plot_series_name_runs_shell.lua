-- a robot name and a run folder name that gnuplot runs as shell commands
local robot = gaitlab.robot.chain{ name = "`touch gaitlab_injected`", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = "runs/p" }
sim:step(10)
sim:record(false)
local run = assert(gaitlab.data.open("runs/p"))
print(pcall(run.plot, run, { series = { "robot" }, output = "p.png" }))
