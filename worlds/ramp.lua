-- worlds/ramp.lua: a ramp rising towards +x from x = 0, with a flat top. The robot starts on
-- the slope, head uphill: a gait that moves it head first (phase < 0) makes it climb.
return gaitlab.world.preset{
  name = "ramp",
  description = "a ramp rising towards +x from x = 0 to a flat top; the robot starts on the " ..
    "slope, 10 cm from its foot, head uphill",
  params = {
    slope = { 10, min = 1, max = 45, unit = "deg", doc = "angle of the slope" },
    length = { 1.0, min = 0.3, max = 10, unit = "m", doc = "horizontal run of the slope" },
    width = { 0.6, min = 0.1, max = 10, unit = "m", doc = "width of the ramp and the top" },
    top = { 0.5, min = 0, max = 10, unit = "m", doc = "length of the flat top (0: none)" },
    friction = { 0.8, min = 0, max = 1, doc = "friction of the floor, the ramp and the top" },
  },
  build = function(p)
    local world = gaitlab.world{ floor = { friction = p.friction } }
    world:ramp{ slope = p.slope, length = p.length, width = p.width, friction = p.friction }
    local rise = p.length * math.tan(math.rad(p.slope))
    if p.top > 0 then
      world:box{ size = { p.top, p.width, rise }, position = { p.length + p.top / 2, 0, rise / 2 },
                 friction = p.friction }
    end
    -- the tail's lower edge 10 cm (horizontally) up the slope, the robot tilted onto it
    local x = 0.1
    return world, { x = x, z = x * math.tan(math.rad(p.slope)) + 0.001, pitch = p.slope }
  end,
}
