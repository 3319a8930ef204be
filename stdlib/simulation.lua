-- gaitlab.simulation.run_file(path): what `gaitlab run FILE.xml` does. Loads the simulation
-- file and the parts it names, runs it for its duration and prints how far each robot moved.
local gaitlab = ...

function gaitlab.simulation.run_file(path)
  local sim, setup = gaitlab.simulation.load(path)
  if not sim then error(setup, 0) end
  sim:run(setup.duration)
  local names = {}
  for name in pairs(setup.robots) do names[#names + 1] = name end
  table.sort(names)
  for _, name in ipairs(names) do
    local d = setup.robots[name]:displacement()
    print(string.format("%s: moved %.3f m (x %.3f, y %.3f) in %g s", name, d:norm(), d.x, d.y,
      sim.time))
  end
  return sim, setup
end
