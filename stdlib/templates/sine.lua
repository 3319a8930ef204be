-- A sine-wave gait: every joint of the group swings like a sine, each joint shifted in phase
-- from its tail-side neighbour, so a wave runs along the body (Gonzalez-Gomez's generator):
--
--   angle of joint m = amplitude * sin(2 pi frequency t + (m - 1) phase + phase0) + offset
--
-- Change a number, save the file: the running simulation picks the new version up.
return gaitlab.controller{
  name = "my_sine",
  params = {                                          -- { default, min =, max =, unit = }
    amplitude = { 40,  min = 0,    max = 90,  unit = "deg" },  -- how far each joint swings
    frequency = { 0.5, min = 0,    max = 5,   unit = "Hz"  },  -- swings per second
    phase     = { 120, min = -180, max = 180, unit = "deg" },  -- shift between neighbours
    phase0    = { 0,   min = -180, max = 180, unit = "deg" },  -- shift of the whole wave
    offset    = { 0,   min = -90,  max = 90,  unit = "deg" },  -- angle the swing is centred on
  },
  values = { "time", "angle" },                       -- per joint: recorded and plottable
  step = function(self, dt)                           -- runs every control tick
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self.angle[m] = self.amplitude
        * math.sin(2 * math.pi * self.frequency * self.time[m]
                   + (m - 1) * math.rad(self.phase) + math.rad(self.phase0))
        + self.offset
      self:set_angle(m, self.angle[m])
    end
  end,
}
