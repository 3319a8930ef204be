-- examples/optimize/snake_sweep.lua: the 8-module pitch-pitch snake's speed over a grid of sine
-- phases and frequencies (a parameter sweep: a table and a heat map):
--   gaitlab sweep examples/optimize/snake_sweep.lua --grid phase=0:180:15 frequency=0.25:1:0.25 --workers 2
-- The same spec form as gaitlab optimize's (examples/optimize/snake_speed.lua), with ranges wide
-- enough for that grid and shorter runs (settle 1 s, measure 5 s): 52 points. The amplitude is
-- not swept: it stays at its initial value, 40.
return {
  parameters = {
    amplitude = { 10, 60, initial = 40 },     -- deg
    frequency = { 0.25, 1.5, initial = 0.5 }, -- Hz
    phase = { 0, 180, initial = 120 },        -- deg, phase lead of each joint
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
  duration = 5,
}
