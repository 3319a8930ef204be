-- a controller that resets, steps and records its own simulation from inside its step
local sim
local Meddle = gaitlab.controller{
  name = "meddle",
  step = function(self, dt)
    self.n = (self.n or 0) + 1
    print(pcall(sim.reset, sim))
    print(pcall(sim.step, sim, 1))
    print(pcall(sim.run, sim, 0.01))
    print(pcall(sim.record, sim, "runs/inside"))
    print(pcall(sim.save, sim, "inside.xml"))
  end,
}
local robot = gaitlab.robot.chain{ modules = 3 }
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(Meddle())
sim = gaitlab.simulation{ world = world, control_every = 10 }
print(pcall(sim.step, sim, 60))
print(sim.ticks, sim.time)
