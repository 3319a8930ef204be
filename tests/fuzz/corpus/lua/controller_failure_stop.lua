-- on_controller_error = "stop" (the default): sim:run raises the controller's error
local Stop = gaitlab.controller{
  name = "stop",
  step = function(self, dt) local t = nil; return t.x end,
}
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Stop())
local sim = gaitlab.simulation{ world = world }
print(pcall(sim.run, sim, 0.5))
print(ctl.failed, ctl.error, sim.ticks)
print(pcall(sim.step, sim, 10))
sim:reset()
print(pcall(sim.step, sim, 40))
