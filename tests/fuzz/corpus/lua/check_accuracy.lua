-- sim:check_accuracy: the world run again at dt / 4 and 4x the iterations; hostile seconds,
-- cycles and settling times; a controller that fails in the check's runs; the simulation
-- checked is not touched
local n = 0
local Flaky = gaitlab.controller{
  name = "flaky",
  step = function(self, dt)
    n = n + 1
    if n % 7 == 0 then error("flaky " .. n) end
    self:set_angle(1, 20 * math.sin(n / 10))
  end,
}
local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
local world = gaitlab.world{}
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30, phase = 120 })
local sim = gaitlab.simulation{ world = world, solver = "pgs", solver_iterations = 2 }
sim:run(0.05)
local r = sim:check_accuracy{ seconds = 0.2, cycle = 0.05, settle = 0.05 }
print(#r.robots, #r.warnings, r.robots[1].given.path, sim.time)
for _, bad in ipairs({ { seconds = 0 }, { seconds = 0 / 0 }, { seconds = 1 / 0 }, { seconds = 2 ^ 63 },
                       { cycle = -1 }, { cycle = 1e-9 }, { settle = 20 }, { settle = -0.0, seconds = 0.1 },
                       { seconds = "x" }, { seconds = {} }, { sekonds = 1 } }) do
  print(pcall(sim.check_accuracy, sim, bad))
end
print(pcall(sim.check_accuracy, sim, 3))
print(pcall(sim.check_accuracy))
local world2 = gaitlab.world{}
local robot2 = gaitlab.robot.chain{ name = "flaky", modules = 2 }
world2:add(robot2)
robot2:group("pitch"):drive(Flaky())
for _, policy in ipairs({ "stop", "continue", "pause" }) do
  local s = gaitlab.simulation{ world = world2, on_controller_error = policy, control_every = 3 }
  print(policy, pcall(s.check_accuracy, s, { seconds = 0.1, cycle = 0.05 }))
end
