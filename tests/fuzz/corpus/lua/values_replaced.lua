-- a step that replaces its value arrays, its joint count and its parameters with wrong things
local Odd = gaitlab.controller{
  name = "odd",
  params = { amplitude = { 10, min = 0, max = 20 } },
  values = { "time", "angle" },
  step = function(self, dt)
    self.n = (self.n or 0) + 1
    local k = self.n % 6
    if k == 0 then self.time = nil
    elseif k == 1 then self.time = "time"
    elseif k == 2 then self.angle = setmetatable({}, { __index = function() error("no") end })
    elseif k == 3 then self.joints = 1e9
    elseif k == 4 then self.amplitude = 0 / 0
    else self.angle = { 1 / 0, -1 / 0, 0 / 0 } end
    for m = 1, 3 do self:set_angle(m, self.amplitude) end
  end,
}
local robot = gaitlab.robot.chain{ modules = 3 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Odd())
local sim = gaitlab.simulation{ world = world, on_controller_error = "continue", control_every = 2 }
for _ = 1, 6 do
  sim:step(2)
  print(ctl.failed, ctl.error, pcall(ctl.values, ctl))
  sim:reset()
end
