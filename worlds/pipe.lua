-- worlds/pipe.lua: a pipe lying along +x on the floor, with the robot inside it.
return gaitlab.world.preset{
  name = "pipe",
  description = "a pipe lying on the floor along +x from x = -entrance; the robot starts " ..
    "inside, on its bottom (modules up to 60 mm wide fit)",
  params = {
    radius = { 0.08, min = 0.05, max = 1, unit = "m", doc = "inner radius" },
    thickness = { 0.01, min = 0.001, max = 0.1, unit = "m", doc = "wall thickness" },
    length = { 1.5, min = 0.3, max = 20, unit = "m", doc = "length of the pipe" },
    sides = { 24, min = 6, max = 128, integer = true, doc = "flat walls around the pipe" },
    entrance = { 0.2, min = 0, max = 10, unit = "m", doc = "how far behind the origin it starts" },
    friction = { 0.8, min = 0, max = 1, doc = "friction of the floor and the pipe" },
  },
  build = function(p)
    local world = gaitlab.world{ floor = { friction = p.friction } }
    local axis = p.radius + p.thickness
    world:pipe{ radius = p.radius, thickness = p.thickness, length = p.length, sides = p.sides,
                position = { -p.entrance, 0, axis }, friction = p.friction }
    -- low enough to rest on the curved bottom, high enough that a body 60 mm wide clears it
    return world, { z = axis - math.sqrt(p.radius ^ 2 - 0.03 ^ 2) + 0.001 }
  end,
}
