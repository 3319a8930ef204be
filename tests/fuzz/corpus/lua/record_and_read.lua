-- a recorded run read back: series, selections, ranges, events, log, exports
local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 20 })
local sim = gaitlab.simulation{ world = world, record = { dir = "runs/r", record_every = 5,
  flush_seconds = 0, series = { "snake.com.*", "snake.angle[*]", "sine.*" } } }
print(sim.record_dir)
sim:step(100)
ctl.amplitude = 30
print("a line for the log")
sim:flush()
sim:step(100)
sim:record(false)
local run = assert(gaitlab.data.open("runs/r"))
print(run, run.dir, run.name, run.status, run.message, run.rows, run.truncated, run.script,
      run.seed, run.started, run.dt, run.provenance)
print(#run:series(), #run:select("snake.*"), #run:select{ "robot", "sine.*" })
local x = run:get("snake.com.x", { from = 0.01, to = 0.1 })
print(x.name, x.kind, x.unit, #x.time, #x.values)
print(run:get{ kind = "robot", value = "angle", joint = 2 }.name)
print(#run:events(), #run:log())
print(pcall(run.get, run, "snake.angel[1]"))
print(run:export{ series = { "snake.com.x" }, file = "x.csv" })
print(pcall(run.export, run, { series = { "snake.com.x" }, file = "no/such/x.csv" }))
print(run:export{ series = { "sine.*" }, dir = "out/split", from = 0, to = 0.1 })
print(gaitlab.data.open("runs"))
print(gaitlab.data.open("nowhere"))
