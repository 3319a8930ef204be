-- One measured run of a chain robot on a flat floor, shared by bench/lua/convergence.lua and
-- bench/lua/drift.lua: the run starts at time 0, settles, then measures a number of cycles; the
-- control period stays 10 ms at every dt.
--
--   local chain_run = require "chain_run"
--   local r = chain_run{ modules =, connection =, friction =, dt =, iterations =,
--                        settle =, cycles =, frequency =, drive = function(robot) ... end,
--                        solver = (optional: the simulation's solver, default the engine's),
--                        newton_steps = (optional: the simulation's newton_steps, default the
--                                        engine's: 8 for a pitch-yaw chain of 13 modules or more),
--                        module = (optional: the chain's module type, default y1),
--                        self_collision = (optional: the chain's self_collision, default false),
--                        floor = (optional: the floor's other keys, bench/lua/floor_env.lua),
--                        settle_at = (optional: { dt =, iterations = }, the settings the run
--                                     settles at; it then goes on at dt and iterations from
--                                     the settled state, sim:clone{...}: the motion settled
--                                     into, continued at other settings) }
--   -- r.x, r.y: mm per cycle along x (the chain's axis at the start) and across it (y);
--   -- r.speed: the per-cycle speed, the mean over the cycles of the length of each cycle's
--   -- horizontal displacement (mm), which a robot that turns slowly keeps; r.tilt: the bodies'
--   -- mean tilt (deg, 0 upright, 90 on their side, 180 upside down) over the measured cycles,
--   -- sampled every 0.1 s, which tells a long pitch-yaw chain's motions apart (upright or
--   -- lying twisted on its side, docs/performance.md section 12); r.cpu: CPU seconds of the run
local posture = require "posture"

return function(o)
  local robot = gaitlab.robot.chain{ name = "snake", modules = o.modules,
                                     connection = o.connection, module = o.module,
                                     self_collision = o.self_collision }
  local world = gaitlab.world{ floor = require("floor_env").on(o.floor or {}, o.friction) }
  world:add(robot)
  o.drive(robot)
  local first = o.settle_at or { dt = o.dt, iterations = o.iterations }
  local sim = gaitlab.simulation{ world = world, dt = first.dt,
                                  control_every = math.floor(0.01 / first.dt + 0.5),
                                  solver_iterations = first.iterations, solver = o.solver,
                                  newton_steps = o.newton_steps,
                                  record = false }
  local t0 = os.clock()
  sim:run(o.settle)
  if o.settle_at then
    sim = sim:clone{ dt = o.dt, control_every = math.floor(0.01 / o.dt + 0.5),
                     solver_iterations = o.iterations }
  end
  local r = sim:robot("snake")
  local p0 = r:position()
  local last, length = p0, 0
  local tilt, samples = 0, 0
  local slices = math.max(1, math.floor(10 / o.frequency + 0.5))  -- of 0.1 s
  for _ = 1, o.cycles do
    for _ = 1, slices do
      sim:run(1 / o.frequency / slices)
      tilt = tilt + posture(r)
      samples = samples + 1
    end
    local p = r:position()
    length = length + math.sqrt((p.x - last.x) ^ 2 + (p.y - last.y) ^ 2)
    last = p
  end
  local d = last - p0
  return { x = 1000 * d.x / o.cycles, y = 1000 * d.y / o.cycles,
           speed = 1000 * length / o.cycles, tilt = tilt / samples, cpu = os.clock() - t0 }
end
