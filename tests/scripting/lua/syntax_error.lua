-- a controller file that does not parse
return gaitlab.controller{
  name = "broken"
  step = function(self, dt) end,
}
