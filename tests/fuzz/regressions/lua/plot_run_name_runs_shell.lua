-- a run folder whose name holds a newline and a gnuplot command
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = "run\nsystem 'touch gaitlab_injected'" }
sim:step(10)
sim:record(false)
local run = assert(gaitlab.data.open("run\nsystem 'touch gaitlab_injected'"))
print(run.name)
print(pcall(run.plot, run, { series = { "snake.com.x" }, output = "p.png" }))
