-- bench/optimize_throughput.sh: an optimization spec whose evaluations are short (the 8-module
-- pitch-pitch snake of examples/optimize/snake_speed.lua for DURATION simulated seconds, env
-- GAITLAB_BENCH_DURATION, default 1), to count evaluations per second and the runner's own cost
local duration = tonumber(os.getenv("GAITLAB_BENCH_DURATION") or "1")
return {
  parameters = {
    amplitude = { 10, 60, initial = 40 },
    frequency = { 0.2, 1.5, initial = 0.5 },
    phase = { 30, 180, initial = 120 },
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
  duration = duration,
  method = "cmaes",
  population = 16,
}
