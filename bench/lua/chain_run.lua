-- One measured run of a chain robot on a flat floor, shared by bench/lua/convergence.lua and
-- bench/lua/drift.lua: the run starts at time 0, settles, then measures a number of cycles; the
-- control period stays 10 ms at every dt.
--
--   local chain_run = require "chain_run"
--   local r = chain_run{ modules =, connection =, friction =, dt =, iterations =,
--                        settle =, cycles =, frequency =, drive = function(robot) ... end,
--                        solver = (optional: the simulation's solver, default the engine's) }
--   -- r.x, r.y: mm per cycle along x (the chain's axis at the start) and across it (y);
--   -- r.cpu: CPU seconds of the run
return function(o)
  local robot = gaitlab.robot.chain{ name = "snake", modules = o.modules,
                                     connection = o.connection }
  local world = gaitlab.world{ floor = { friction = o.friction } }
  world:add(robot)
  o.drive(robot)
  local sim = gaitlab.simulation{ world = world, dt = o.dt,
                                  control_every = math.floor(0.01 / o.dt + 0.5),
                                  solver_iterations = o.iterations, solver = o.solver,
                                  record = false }
  local r = sim:robot("snake")
  local t0 = os.clock()
  sim:run(o.settle)
  local p0 = r:position()
  sim:run(o.cycles / o.frequency)
  local d = r:position() - p0
  return { x = 1000 * d.x / o.cycles, y = 1000 * d.y / o.cycles, cpu = os.clock() - t0 }
end
