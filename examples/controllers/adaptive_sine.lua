-- A sine gait with joint feedback: it watches how far its joints really swing and slows down
-- until the servos can follow it. A servo turns at most 4.5 rad/s, so a 60 deg swing at 3 Hz is
-- out of reach: a plain sine would leave the joints swinging a fraction of the amplitude asked.
--
-- Every control tick it reads the measured angle of each joint (self:joint_angle(m), degrees). At the
-- end of each cycle it compares the widest swing of the least-swinging joint with `tolerance` x
-- `amplitude`: too small, the frequency drops by 15%; large enough, it climbs back by 5% towards
-- the `frequency` asked for.
return gaitlab.controller{
  name = "adaptive_sine",
  params = {
    amplitude = { 40,  min = 0,    max = 90,  unit = "deg" },
    frequency = { 0.5, min = 0.05, max = 5,   unit = "Hz"  },  -- the frequency asked for
    phase     = { 120, min = -180, max = 180, unit = "deg" },
    tolerance = { 0.9, min = 0.1,  max = 1,   unit = ""    },  -- share of the amplitude to reach
  },
  -- per joint: the angle commanded, the widest swing measured in the last whole cycle (deg),
  -- and the frequency the gait runs at (the same for every joint)
  values = { "angle", "reached", "running" },
  step = function(self, dt)
    local f = math.min(self.running[1] > 0 and self.running[1] or self.frequency, self.frequency)
    self.phi = (self.phi or 0) + 2 * math.pi * f * dt
    self.peak = self.peak or {}
    if self.phi >= 2 * math.pi then                 -- a cycle is over: adapt
      self.phi = self.phi - 2 * math.pi
      local worst = math.huge
      for m = 1, self.joints do
        self.reached[m] = self.peak[m] or 0
        worst = math.min(worst, self.reached[m])
        self.peak[m] = 0
      end
      if worst < self.tolerance * self.amplitude then
        f = math.max(0.05, f * 0.85)
      else
        f = math.min(self.frequency, f * 1.05)
      end
    end
    for m = 1, self.joints do
      self.peak[m] = math.max(self.peak[m] or 0, math.abs(self:joint_angle(m)))
      self.running[m] = f
      self.angle[m] = self.amplitude * math.sin(self.phi + (m - 1) * math.rad(self.phase))
      self:set_angle(m, self.angle[m])
    end
  end,
}
