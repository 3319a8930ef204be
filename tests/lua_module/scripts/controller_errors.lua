-- Lua controllers that fail inside sim:run: reported and skipped under "continue", paused under
-- "pause", and under "stop" (the default) the error that ends the script.
local function snake(policy, step)
  local robot = gaitlab.robot.chain{ name = "snake", modules = 3 }
  local world = gaitlab.world()
  world:add(robot)
  robot:group("all"):drive(gaitlab.controller{ name = "flaky", step = step }())
  return gaitlab.simulation{ world = world, on_controller_error = policy }, robot
end
local n = 0
local sim = snake("continue", function(self)
  n = n + 1
  if n % 5 == 0 then error("every fifth step fails") end
  self:set_angle(1, 10)
end)
sim:run(0.5)
print("continue: ran to", sim.time)
sim = snake("pause", function() error({ "a table as the error" }) end)
sim:run(0.5)
print("pause: stopped at", sim.time, sim.paused)
-- a budget that runs out, however the step swallows errors
sim = snake("continue", function()
  while true do pcall(function() while true do end end) end
end)
sim:run(0.1)
-- a coroutine inside the step runs under the step's budget too
sim = snake("continue", function()
  local co = coroutine.wrap(function() while true do end end)
  co()
end)
sim:run(0.1)
print("budgets: ran to", sim.time)
sim = snake("stop", function(self) self:set_angle(1, self.gain) end)
sim:run(1)
