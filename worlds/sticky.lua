-- worlds/sticky.lua: a sticky floor (friction 1, like rubber on rubber).
return gaitlab.world.preset{
  name = "sticky",
  description = "a flat floor of friction 1; the robot starts at the origin",
  params = {
    friction = { 1.0, min = 0, max = 1, doc = "friction of the floor" },
  },
  build = function(p)
    return gaitlab.world{ floor = { friction = p.friction } }, {}
  end,
}
