-- controllers/shuttle.lua: a sine gait that turns back before it hits a wall (sensor feedback).
--
-- It reads two range sensors of its robot: "back", on the tail looking behind, and "front", on
-- the head looking ahead (see examples/shuttle.lua for how to attach them). It crawls tail first;
-- when the sensor on the side it is going reports an object closer than `near`, it reverses its
-- travelling wave and crawls the other way. A sensor that is switched off reads nil: the
-- controller then sees nothing and keeps going.
return gaitlab.controller{
  name = "shuttle",
  params = {
    amplitude = { 40,  min = 0,    max = 90,  unit = "deg" },
    frequency = { 1,   min = 0,    max = 5,   unit = "Hz"  },
    phase     = { 120, min = 0,    max = 180, unit = "deg" },   -- lag between neighbours
    near      = { 0.1, min = 0.01, max = 2,   unit = "m"   },   -- turn back when this close
  },
  values = { "time", "angle" },
  step = function(self, dt)
    -- self.heading: -1 tail first (towards -x), +1 head first; self.turns counts reversals
    self.heading = self.heading or -1
    self.turns = self.turns or 0
    local ahead = self:sensor(self.heading < 0 and "back" or "front")
    if ahead and ahead.hit and ahead.distance < self.near then
      self.heading = -self.heading
      self.turns = self.turns + 1
    end
    -- a wave running from head to tail (phase > 0) moves a pitch-pitch robot tail first
    local phase = math.rad(self.phase) * -self.heading
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self.angle[m] = self.amplitude
        * math.sin(2 * math.pi * self.frequency * self.time[m] + (m - 1) * phase)
      self:set_angle(m, self.angle[m])
    end
  end,
}
