-- parameters changed before and during a run, by every origin; values out of range are errors
local robot = gaitlab.robot.chain{ modules = 4 }
local world = gaitlab.world{}
world:add(robot)
local sine = robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30 })
sine.frequency = 1
local sim = gaitlab.simulation{ world = world, record = "runs/params" }
sim:step(100)
sine:set("amplitude", 20, "console")
sine:set("phase", -90, "viewer")
sine:set("offset", 5)
print(pcall(function() sine.amplitude = 120 end))
print(pcall(function() sine.nope = 1 end))
print(pcall(sine.set, sine, "frequency", 0 / 0))
print(pcall(sine.set, sine, "frequency", 1, "file"))
sim:step(100)
sim:record(false)
local run = gaitlab.data.open("runs/params")
for _, e in ipairs(run:events()) do print(e.tick, e.origin, e.kind, e.name, e.value) end
