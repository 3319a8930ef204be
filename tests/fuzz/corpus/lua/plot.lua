-- a recorded run plotted through gnuplot, with a title of its own
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(gaitlab.controllers.sine{})
local sim = gaitlab.simulation{ world = world, record = "runs/p" }
sim:step(60)
sim:record(false)
local run = assert(gaitlab.data.open("runs/p"))
print(run:plot{ series = { "snake.angle[1]", "sine.amplitude" }, output = "plots/a.png",
                title = "angles, and \"quotes\"", width = 200, height = 150, from = 0, to = 0.05 })
print(pcall(run.plot, run, { series = { "snake.angle[1]" }, output = "a.jpg" }))
print(pcall(run.plot, run, { series = {}, output = "b.png" }))
print(pcall(run.plot, run, { series = { "snake.angle[1]" }, output = "c.png", width = 5 }))
