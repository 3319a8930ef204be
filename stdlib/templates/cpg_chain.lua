-- A central pattern generator (CPG): one oscillator per joint, each pulled towards its
-- neighbours so that they settle a fixed phase lag apart (the amplitude-controlled phase
-- oscillators of Ijspeert's salamander and AmphiBot robots). Unlike a sine, the wave builds up
-- by itself and stays smooth when you change a parameter while it runs.
--
--   d(theta_m)/dt = 2 pi frequency + coupling * sum over neighbours j of
--                   r_j * sin(theta_j - theta_m -/+ lag)
--   d2(r_m)/dt2   = gain * (gain / 4 * (amplitude - r_m) - d(r_m)/dt)
--   angle_m       = r_m * sin(theta_m) + offset
--
-- The equations are stepped with small Euler steps (at most 5 ms) inside each control tick.
return gaitlab.controller{
  name = "my_cpg",
  params = {
    amplitude = { 40,  min = 0,    max = 90,  unit = "deg" },  -- the swing the CPG settles to
    frequency = { 0.5, min = 0,    max = 5,   unit = "Hz"  },
    phase     = { 120, min = -180, max = 180, unit = "deg" },  -- lag between neighbours
    offset    = { 0,   min = -90,  max = 90,  unit = "deg" },
    coupling  = { 10,  min = 0,    max = 100, unit = "1/s" },  -- how hard neighbours pull
    gain      = { 20,  min = 0,    max = 200, unit = "1/s" },  -- how fast the amplitude follows
  },
  values = { "theta", "radius", "angle" },            -- phase (rad), amplitude (deg), output
  step = function(self, dt)
    local n = self.joints
    local theta, radius = self.theta, self.radius
    self.speed = self.speed or {}                     -- d(radius)/dt, kept between ticks
    local speed = self.speed
    local omega, lag = 2 * math.pi * self.frequency, math.rad(self.phase)
    local w, a = self.coupling, self.gain
    local substeps = math.ceil(dt / 0.005)
    local h = dt / substeps
    for _ = 1, substeps do
      local dtheta = {}
      for m = 1, n do
        local d = omega
        if m > 1 then d = d + w * math.rad(radius[m - 1]) * math.sin(theta[m - 1] - theta[m] + lag) end
        if m < n then d = d + w * math.rad(radius[m + 1]) * math.sin(theta[m + 1] - theta[m] - lag) end
        dtheta[m] = d
      end
      for m = 1, n do
        theta[m] = (theta[m] + h * dtheta[m]) % (2 * math.pi)
        local accel = a * (a / 4 * (self.amplitude - radius[m]) - (speed[m] or 0))
        radius[m] = radius[m] + h * (speed[m] or 0)
        speed[m] = (speed[m] or 0) + h * accel
      end
    end
    for m = 1, n do
      self.angle[m] = radius[m] * math.sin(theta[m]) + self.offset
      self:set_angle(m, self.angle[m])
    end
  end,
}
