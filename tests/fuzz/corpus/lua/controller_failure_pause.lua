-- on_controller_error = "pause": sim:run returns at the failing tick with sim.paused set
local n = 0
local Flaky = gaitlab.controller{
  name = "flaky",
  step = function(self, dt)
    n = n + 1
    if n % 4 == 0 then error({ code = n }) end
  end,
}
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("pitch"):drive(Flaky())
local sim = gaitlab.simulation{ world = world, on_controller_error = "pause", control_every = 3 }
for _ = 1, 4 do
  sim:run(0.1)
  print(sim.ticks, sim.paused, ctl.failed, ctl.error)
end
