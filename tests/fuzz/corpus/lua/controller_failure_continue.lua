-- a controller that fails under on_controller_error = "continue": the run goes on, the group holds
local Bad = gaitlab.controller{
  name = "bad",
  step = function(self, dt)
    self.n = (self.n or 0) + 1
    if self.n == 3 then error("third step fails") end
    if self.n == 6 then error(setmetatable({}, { __tostring = function() return "an object" end })) end
    self:set_angle(1, 10)
  end,
}
local robot = gaitlab.robot.chain{ modules = 3 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Bad())
local other = robot:group{ 2 }:drive(gaitlab.controllers.sine{})
local sim = gaitlab.simulation{ world = world, on_controller_error = "continue", control_every = 5 }
sim:step(50)
print(ctl.failed, ctl.error, other.failed)
sim:reset()
print(ctl.failed, ctl.error)
sim:step(50)
print(ctl.failed, ctl.error)
