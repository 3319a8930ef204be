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

-- gaitlab.simulation.check_file(path, { seconds =, cycle =, settle = }): what `gaitlab check
-- FILE.xml` does. Loads the simulation file, runs sim:check_accuracy on it (seconds default: the
-- file's duration) and prints one line per robot: its path at the file's settings, at dt / 4
-- and at 4x the iterations. The warnings are reported as the check's are; returns the report.
-- Errors name the simulation file, as run_file's do.
function gaitlab.simulation.check_file(path, options)
  local sim, setup = gaitlab.simulation.load(path)
  if not sim then error(setup, 0) end
  local function fail(message) error(format("%s:%d: %s", path, setup.line, message), 0) end
  local o = options or {}
  local seconds, settle = o.seconds or setup.duration, o.settle or 0
  local cycle = o.cycle or math.min(1, seconds - settle)
  if not (seconds > 0) then
    fail(format("the check runs for the file's duration, %g s: give it a duration > 0", seconds))
  end
  if not (settle < seconds) then
    fail(format("the settling time (%g s) must be shorter than the check (%g s)", settle, seconds))
  end
  if not (cycle >= sim.dt and cycle <= seconds - settle) then
    fail(format("the cycle (%g s) must be from dt (%g s) to the time checked after the settling"
      .. " time (%g s)", cycle, sim.dt, seconds - settle))
  end
  local ok, report = pcall(sim.check_accuracy, sim, { seconds = seconds, cycle = cycle,
    settle = settle })
  -- called through pcall, the check's argument errors name no function: keep what they say
  if not ok then fail((tostring(report):gsub("^bad argument #%d+ to '%?' %((.*)%)$", "%1"))) end
  local s = report.settings
  print(format("%s: the paths from %g to %g s, sampled every %g s, at the file's dt %g ms and"
    .. " %d iterations, at dt %g ms and with %d iterations", path, report.settle, report.seconds,
    report.cycle, s.given.dt * 1000, s.given.solver_iterations,
    (s.dt or s.given).dt * 1000, s.iterations.solver_iterations))
  for _, r in ipairs(report.robots) do
    local dt = r.dt and format("at dt / 4 %.1f mm (%+.1f %%)", r.dt.path * 1000, r.dt_off)
      or "dt / 4 not checked (below 1 us)"
    print(format("%s: path %.1f mm; %s; with 4x the iterations %.1f mm (%+.1f %%)", r.name,
      r.given.path * 1000, dt, r.iterations.path * 1000, r.iterations_off))
  end
  print(#report.warnings == 0 and "within 3 % at both finer settings"
    or format("%d setting(s) move a robot by more than 3 %% (the warnings above)",
      #report.warnings))
  return report
end

-- how sim:status() prints: a few lines a console shows as they are
local registry = select(2, ...)
local concat = table.concat

-- {1, 2, 3, 5} -> "1-3, 5"
local function ranges(list)
  local out, i = {}, 1
  while i <= #list do
    local j = i
    while j < #list and list[j + 1] == list[j] + 1 do j = j + 1 end
    out[#out + 1] = j > i and format("%d-%d", list[i], list[j]) or tostring(list[i])
    i = j + 1
  end
  return concat(out, ", ")
end

local function rate(x)
  if x == math.huge then return "as fast as possible" end
  return format("at %gx real time", x)
end

registry["gaitlab.Status"] = {
  __name = "gaitlab.Status",
  __metatable = "gaitlab.Status",
  __tostring = function(s)
    local state
    if s.playing then
      state = "playing " .. rate(s.speed)
      if s.delay > 0 then state = state .. format(" with a delay of %g s per step", s.delay) end
      state = state .. (s.factor and format(", measured %.2fx real time", s.factor)
        or ", measuring the real-time factor")
    else
      state = "paused (speed " .. (s.speed == math.huge and "math.huge" or format("%g", s.speed))
        .. format(", delay %g s)", s.delay)
    end
    local lines = { format("simulation %d: t = %.3f s, %s", s.simulation, s.time, state) }
    if s.failure then
      lines[#lines + 1] = "  " .. s.failure .. "; sim:reset() to play it again"
    end
    for _, r in ipairs(s.robots) do
      local p = r.position
      lines[#lines + 1] = format(
        "  robot %s at (%.3f, %.3f, %.3f) m, heading %.1f deg, turned %.1f deg",
        r.name, p.x, p.y, p.z, r.heading, r.turned)
    end
    for _, c in ipairs(s.controllers) do
      local params = {}
      for _, p in ipairs(c.params) do
        params[#params + 1] = format("%s = %g%s", p.name, p.value,
          p.unit ~= "" and " " .. p.unit or "")
      end
      local line = format("  controller %s on %s joints %s, %s", c.name, c.robot,
        ranges(c.joints), c.state)
      if c.error then line = line .. " (" .. c.error:match("[^\n]*") .. ")" end
      if #params > 0 then line = line .. ": " .. concat(params, ", ") end
      lines[#lines + 1] = line
    end
    return concat(lines, "\n")
  end,
}
