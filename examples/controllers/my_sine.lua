-- controllers/my_sine.lua: a user-defined controller module
return gaitlab.controller{
  name = "my_sine",
  params = {
    amplitude = { 40,  min = 0,    max = 90,  unit = "deg" },
    frequency = { 0.5, min = 0,    max = 5,   unit = "Hz"  },
    phase     = { 120, min = -180, max = 180, unit = "deg" },
  },
  values = { "time", "angle" },                   -- per joint; recorded and plottable
  step = function(self, dt)                        -- every control tick
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self.angle[m] = self.amplitude
        * math.sin(2 * math.pi * self.frequency * self.time[m] + (m - 1) * math.rad(self.phase))
      self:set_angle(m, self.angle[m])
    end
  end,
}
