-- Record a gait, read it back and plot it. `gaitlab run` records every simulation into a run
-- folder (runs/NAME-DATE-TIME, or --record DIR); sim.record_dir says which. See docs/data.md.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
local ctl = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, phase = -120 })

-- record only what this example looks at: the centre of mass, the joint angles, the sine
local sim = gaitlab.simulation{ world = world,
  record = { series = { "snake.com.*", "snake.angle[*]", "sine.*", "snake.energy" } } }
sim:run(10)
ctl.amplitude = 20                                 -- an event in events.csv, at t = 10 s
sim:run(10)

local dir = sim.record_dir
if not dir then                                    -- gaitlab run --no-record
  print("not recorded")
  return
end
sim:record(false)                                  -- close the run folder: everything is on disk

local run = assert(gaitlab.data.open(dir))
local x = run:get("snake.com.x")
local e = run:get("snake.energy")
print(string.format("%d rows of %d series; x went from %.3f to %.3f m using %.2f J",
  #x.time, #run:series(), x.values[1], x.values[#x.values], e.values[#e.values]))
local slow = run:get("snake.com.x", { from = 10 })  -- the second half only
print(string.format("after the change: %.3f m in %.0f s", slow.values[#slow.values] - slow.values[1],
  slow.time[#slow.time] - slow.time[1]))

-- a PNG through gnuplot; angles.gp and angles.csv stay next to it for editing
local png = run:plot{ series = { "snake.angle[1]", "snake.angle[2]", "sine.amplitude" },
  output = dir .. "/angles.png", from = 8, to = 12 }
print("plot: " .. png)
