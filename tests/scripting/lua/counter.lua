-- counts its control steps per joint and copies its parameter to the targets; reads back what
-- the servos measure
return gaitlab.controller{
  name = "counter",
  params = { level = { 10, min = -45, max = 45, unit = "deg" } },
  values = { "steps", "seen" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.steps[m] = self.steps[m] + 1
      self.seen[m] = self:joint_angle(m) + 0 * self:joint_velocity(m) + 0 * self:joint_torque(m)
      self:set_angle(m, self.level)
    end
  end,
}
