-- a plot title that gnuplot runs as a shell command
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local sim = gaitlab.simulation{ world = world, record = "runs/p" }
sim:step(10)
sim:record(false)
local run = assert(gaitlab.data.open("runs/p"))
print(pcall(run.plot, run, { series = { "snake.com.x" }, output = "p.png", title = "`touch gaitlab_injected`" }))
