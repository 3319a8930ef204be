-- worlds/rubble.lua: a field of random stones under and around the robot.
return gaitlab.world.preset{
  name = "rubble",
  description = "a field of random stones (boxes) centred at x = 0.3; the same seed always " ..
    "gives the same stones; the robot starts just above the tallest stone",
  params = {
    count = { 80, min = 0, max = 5000, integer = true, doc = "number of stones" },
    length = { 2.0, min = 0.1, max = 50, unit = "m", doc = "field size along x" },
    width = { 1.0, min = 0.1, max = 50, unit = "m", doc = "field size along y" },
    min_size = { 0.02, min = 0.002, max = 1, unit = "m", doc = "smallest side of a stone" },
    max_size = { 0.06, min = 0.002, max = 1, unit = "m", doc = "largest side of a stone" },
    min_height = { 0.005, min = 0.001, max = 0.5, unit = "m", doc = "lowest stone" },
    max_height = { 0.02, min = 0.001, max = 0.5, unit = "m", doc = "tallest stone" },
    seed = { 1, min = 0, max = 2 ^ 53, integer = true, doc = "which random field" },
    friction = { 0.8, min = 0, max = 1, doc = "friction of the floor and the stones" },
  },
  check = function(p)
    if p.max_size < p.min_size then
      return string.format("max_size must not be below min_size (got %g < %g m)", p.max_size,
        p.min_size)
    end
    if p.max_height < p.min_height then
      return string.format("max_height must not be below min_height (got %g < %g m)",
        p.max_height, p.min_height)
    end
  end,
  build = function(p)
    local world = gaitlab.world{ floor = { friction = p.friction } }
    world:rubble{ length = p.length, width = p.width, count = p.count, min_size = p.min_size,
                  max_size = p.max_size, min_height = p.min_height, max_height = p.max_height,
                  seed = p.seed, position = { 0.3, 0, 0 }, friction = p.friction }
    return world, { z = p.max_height + 0.002 }
  end,
}
