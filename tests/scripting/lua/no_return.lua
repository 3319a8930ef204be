-- a controller file that forgets to return its controller
local ctl = gaitlab.controller{
  name = "forgotten",
  step = function(self, dt) end,
}
