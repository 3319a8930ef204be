-- worlds/hills.lua: rolling hills, a heightfield sampled from a Lua function.
return gaitlab.world.preset{
  name = "hills",
  description = "a heightfield of rolling hills, h = height/2 (1 - cos(2 pi x/wavelength) " ..
    "cos(2 pi y/wavelength)), centred at x = 0.3; the robot starts just above the highest hill",
  params = {
    height = { 0.04, min = 0, max = 1, unit = "m", doc = "from valley floor to hill top" },
    wavelength = { 0.8, min = 0.1, max = 20, unit = "m", doc = "from one hill top to the next" },
    length = { 3.0, min = 0.2, max = 50, unit = "m", doc = "terrain size along x" },
    width = { 2.0, min = 0.2, max = 50, unit = "m", doc = "terrain size along y" },
    friction = { 0.8, min = 0, max = 1, doc = "friction of the terrain and the floor" },
  },
  build = function(p)
    local world = gaitlab.world{ floor = { friction = p.friction } }
    local k, centre = 2 * math.pi / p.wavelength, 0.3
    world:heightfield{
      length = p.length, width = p.width, position = { centre, 0, 0 }, friction = p.friction,
      resolution = 0.02,
      -- x, y are the terrain's own coordinates: add its centre for world x
      heights = function(x, y)
        return p.height / 2 * (1 - math.cos(k * (x + centre)) * math.cos(k * y))
      end,
    }
    return world, { z = p.height + 0.002 }
  end,
}
