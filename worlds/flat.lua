-- worlds/flat.lua: a flat floor, the world of examples/first_snake.lua.
return gaitlab.world.preset{
  name = "flat",
  description = "a flat floor of friction 0.8; the robot starts at the origin",
  params = {
    friction = { 0.8, min = 0, max = 1, doc = "friction of the floor" },
  },
  build = function(p)
    return gaitlab.world{ floor = { friction = p.friction } }, {}
  end,
}
