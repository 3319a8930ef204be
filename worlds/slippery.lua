-- worlds/slippery.lua: a slippery floor (friction 0.1, like plastic on wet ice).
return gaitlab.world.preset{
  name = "slippery",
  description = "a flat floor of friction 0.1; the robot starts at the origin",
  params = {
    friction = { 0.1, min = 0, max = 1, doc = "friction of the floor" },
  },
  build = function(p)
    return gaitlab.world{ floor = { friction = p.friction } }, {}
  end,
}
