-- examples/optimize/tune.lua: an optimization run from a script with gaitlab.optimize{...}.
--   gaitlab run examples/optimize/tune.lua [METHOD] [GENERATIONS]      (default: cmaes 2)
-- Tunes the 8-module snake's sine for speed as snake_speed.lua (beside this file) says, on two
-- workers, prints the best, then loads the best gait from the simulation file the optimization
-- wrote and runs it again, measured as the spec measures it: the same speed, to the last bit.
-- The same lines work typed in the console (gaitlab, then spec = "examples/optimize/...").
local method = arg[1] or "cmaes"
local generations = math.tointeger(tonumber(arg[2] or "2"))
local r = gaitlab.optimize{
  spec = "snake_speed.lua", method = method, generations = generations, workers = 2, seed = 1,
}
print(string.format("best speed %.4f m/s after %d evaluations (%s, %d generations of %d)",
                    r.fitness, r.evaluations, r.method, r.generations, r.population))
for _, name in ipairs{ "amplitude", "frequency", "phase" } do
  print(string.format("  %-9s %8.3f", name, r.parameters[name]))
end
print("results in " .. r.folder)

-- the best gait again: settle 1 s, then measure 10 s, as the spec's fitness "speed" does
local sim = assert(gaitlab.simulation.load(r.simulation))
local snake = sim:robot("snake")
sim:run(1)
local from = snake:position()
sim:run(10)
local moved = snake:position() - from
local speed = math.sqrt(moved.x ^ 2 + moved.y ^ 2) / 10
print(string.format("run again from %s: %.4f m/s (%s)", r.simulation, speed,
                    speed == r.fitness and "the same" or "differs"))
