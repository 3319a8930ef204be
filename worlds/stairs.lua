-- worlds/stairs.lua: a flight of stairs rising towards +x in front of the robot's head.
return gaitlab.world.preset{
  name = "stairs",
  description = "a flight of stairs rising towards +x, its first step `distance` from the " ..
    "origin, with a landing at the top; the robot starts at the origin, head towards the stairs",
  params = {
    steps = { 3, min = 1, max = 50, integer = true, doc = "number of steps" },
    step_height = { 0.02, min = 0.002, max = 0.3, unit = "m", doc = "rise of each step" },
    step_depth = { 0.25, min = 0.02, max = 2, unit = "m", doc = "tread of each step" },
    width = { 0.6, min = 0.1, max = 10, unit = "m", doc = "width of the stairs" },
    landing = { 0.5, min = 0, max = 10, unit = "m", doc = "extra depth of the top step" },
    distance = { 0.7, min = 0, max = 10, unit = "m", doc = "from the origin to the first step" },
    friction = { 0.8, min = 0, max = 1, doc = "friction of the floor and the stairs" },
  },
  build = function(p)
    local world = gaitlab.world{ floor = { friction = p.friction } }
    world:stairs{ steps = p.steps, step_height = p.step_height, step_depth = p.step_depth,
                  width = p.width, landing = p.landing, position = { p.distance, 0, 0 },
                  friction = p.friction }
    return world, {}
  end,
}
