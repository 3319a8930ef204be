-- examples/optimize/turn.lua: tunes an 8-module pitch-yaw snake for turning rate.
--   gaitlab optimize examples/optimize/turn.lua --workers 2
-- The pitch joints crawl with a sine, the yaw joints are bent by a constant offset: the gait
-- turns (Gonzalez-Gomez et al., CLAWAR 2006). fitness = "heading" is the turning rate in deg/s,
-- counter-clockwise positive seen from above; this snake crawls tail first, so a negative yaw
-- bend turns it counter-clockwise. The search starts from a gentle bend of -5 deg.
return {
  parameters = {
    amplitude = { 10, 60, initial = 40 },     -- deg, pitch sine
    frequency = { 0.2, 1.5, initial = 0.5 },  -- Hz
    phase = { 30, 180, initial = 120 },       -- deg, phase lead of each pitch joint
    bend = { -45, 45, initial = -5 },         -- deg, yaw offset of every yaw joint
  },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
    local world = gaitlab.world{ floor = { friction = 0.8 } }
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{
      amplitude = p.amplitude, frequency = p.frequency, phase = p.phase })
    robot:group("yaw"):drive(gaitlab.controllers.offset{ angle = p.bend })
    return gaitlab.simulation{ world = world, dt = 0.001, control_every = 30 }
  end,
  fitness = "heading",
  settle = 1,
  duration = 6,
  method = "cmaes",
  population = 8,
  generations = 10,
}
