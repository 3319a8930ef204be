-- simulations stepped from coroutines, and a step that tries to yield
local Yield = gaitlab.controller{ name = "yield", step = function(self) coroutine.yield(1) end }
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Yield())
local sim = gaitlab.simulation{ world = world, on_controller_error = "continue" }
local co = coroutine.create(function()
  for i = 1, 3 do
    sim:step(40)
    coroutine.yield(sim.ticks)
  end
end)
while coroutine.status(co) ~= "dead" do print(coroutine.resume(co)) end
print(ctl.failed, ctl.error)
local wrapped = coroutine.wrap(function() sim:reset() coroutine.yield() sim:run(0.05) end)
wrapped()
wrapped()
print(pcall(wrapped))
