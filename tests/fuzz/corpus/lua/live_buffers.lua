-- live buffers of the latest samples while the simulation runs, resized on the way
local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(gaitlab.controllers.hopf{})
local sim = gaitlab.simulation{ world = world }
local live = sim:live{ series = { "snake.com.x", "hopf.x[1]" }, sample_every = 2, refresh = 0, size = 10 }
sim:step(40)
local x = live:get("snake.com.x")
print(#x.time, #x.values, live.size, live.sample_every, live.refresh, live.version, #live.series)
live.size = 3
live.refresh = 0.5
sim:step(40)
for name, s in pairs(live:get()) do print(name, s.time and #s.time) end
print(pcall(live.get, live, "nope"))
print(pcall(function() live.size = 0 end))
print(pcall(function() live.version = 3 end))
print(pcall(sim.live, sim, { series = { "nothing" } }))
