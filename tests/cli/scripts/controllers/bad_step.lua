-- fails at its first control tick: self.gain is not a parameter
return gaitlab.controller{
  name = "bad_step",
  step = function(self, dt)
    self:set_angle(1, self.gain * 10)
  end,
}
