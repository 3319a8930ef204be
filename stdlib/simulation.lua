-- gaitlab.simulation.run_file(path): what `gaitlab run FILE.xml` does. Loads the simulation
-- file and the parts it names, runs it for its duration and prints how far each robot moved.
-- Its errors name the simulation file and the line of its <simulation> element (or the file
-- and line of a part, or of a Lua controller, where the error is theirs), never this file.
local gaitlab = ...
local pcall, error, format = pcall, error, string.format

function gaitlab.simulation.run_file(path)
  local sim, setup = gaitlab.simulation.load(path)
  if not sim then error(setup, 0) end
  -- called through pcall, sim.run has no Lua caller to name: its errors come without a place,
  -- and the place is the file's
  local ok, err = pcall(sim.run, sim, setup.duration)
  if not ok then error(format("%s:%d: %s", path, setup.line, tostring(err)), 0) end
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
