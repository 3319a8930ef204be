-- a world file of the kind users write: a corridor between two walls, with a log across it
return gaitlab.world.preset{
  name = "corridor",
  description = "a corridor along x between two walls, with a log lying across it",
  params = {
    gap = { 0.2, min = 0.1, max = 1, unit = "m", doc = "distance between the walls" },
  },
  build = function(p)
    local world = gaitlab.world()
    world:wall{ length = 2, position = { 0, p.gap / 2 + 0.01, 0 } }
    world:wall{ length = 2, position = { 0, -p.gap / 2 - 0.01, 0 } }
    world:cylinder{ radius = 0.02, length = p.gap, lying = true, yaw = 90,
                    position = { 0.5, 0, 0.02 } }
    return world, { x = -0.5 }
  end,
}
