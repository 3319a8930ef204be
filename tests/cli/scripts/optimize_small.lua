-- a small optimization spec for tests/cli: a 3-module snake for half a second
return {
  parameters = { amplitude = {10, 60, initial = 40}, phase = {30, 180, initial = 120} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = p.amplitude,
                                                         phase = p.phase, frequency = 1 })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  duration = 0.5,
  method = "ga",
  population = 5,
  generations = 3,
}
