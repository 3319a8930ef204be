-- examples/optimize/snake_speed.lua: tunes the sine of the 8-module pitch-pitch snake for speed.
--   gaitlab optimize examples/optimize/snake_speed.lua --workers 2
-- Each evaluation builds the snake with the parameters p, lets it settle for 1 s, runs it for
-- 10 s and measures how fast its centre of mass moved over the floor (m/s). The search starts
-- from the sine's default parameters (amplitude 40, frequency 0.5, phase 120).
return {
  parameters = {
    amplitude = { 10, 60, initial = 40 },     -- deg
    frequency = { 0.2, 1.5, initial = 0.5 },  -- Hz
    phase = { 30, 180, initial = 120 },       -- deg, phase lead of each joint
  },
  build = function(p)
    local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
    local world = gaitlab.world{ floor = { friction = 0.8 } }
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{
      amplitude = p.amplitude, frequency = p.frequency, phase = p.phase })
    return gaitlab.simulation{ world = world, dt = 0.001, control_every = 30 }
  end,
  fitness = "speed",
  settle = 1,
  duration = 10,
  method = "cmaes",
  population = 8,
  generations = 10,
}
