-- a sweep spec for tests/cli whose runs draw from math.random (the sweep's --seed): a 3-module
-- snake whose frequency has a random part, for half a second
return {
  parameters = { amplitude = {10, 60, initial = 40}, phase = {30, 180, initial = 120} },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = p.amplitude, phase = p.phase,
                                                         frequency = 1 + 0.5 * math.random() })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  duration = 0.5,
}
