-- a controller whose step fails at its first control tick
return gaitlab.controller{
  name = "step_error",
  params = { gain = { 1, min = 0, max = 2 } },
  step = function(self, dt)
    local bias = self.gain * self.missing_value
    self:set_angle(1, bias)
  end,
}
