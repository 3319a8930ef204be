-- A blank controller: the smallest complete one, to start your own from. As it is, it holds
-- every joint of its group at `angle`. Write your gait in step(); add parameters (they get a
-- slider in the viewer and can be changed while the simulation runs) and per-joint values (they
-- are recorded and can be plotted).
return gaitlab.controller{
  name = "my_controller",
  params = {
    angle = { 0, min = -90, max = 90, unit = "deg" },
  },
  values = { "time" },                                -- per joint; add your own
  step = function(self, dt)                           -- runs every control tick, dt seconds apart
    for m = 1, self.joints do                         -- joint 1 is nearest the tail
      self.time[m] = self.time[m] + dt
      -- self:joint_angle(m) is where joint m is now (deg); set where it should go:
      self:set_angle(m, self.angle)
    end
  end,
}
