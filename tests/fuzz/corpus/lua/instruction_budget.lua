-- a step that never ends is stopped by its instruction budget, and so are snapshots and loops in hooks
local Spin = gaitlab.controller{
  name = "spin",
  instruction_budget = 1000,
  step = function(self, dt) while true do end end,
}
local Deep = gaitlab.controller{
  name = "deep",
  instruction_budget = 5000,
  step = function(self, dt)
    local function f(n) return f(n + 1) + 1 end
    return f(1)
  end,
}
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local a = robot:group{ 1 }:drive(Spin())
local b = robot:group{ 2 }:drive(Deep())
local sim = gaitlab.simulation{ world = world, on_controller_error = "continue" }
sim:step(100)
print(a.failed, a.error)
print(b.failed, b.error)
print(pcall(gaitlab.controller, { name = "x", step = print, instruction_budget = 0 }))
print(pcall(gaitlab.controller, { name = "x", step = print, instruction_budget = 2^31 }))
