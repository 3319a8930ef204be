-- Sideways drift of the planar gait (issue 14, point 3: "straight means straight"; the drift
-- table of docs/performance.md, section 12): the pitch-pitch travelling wave (40 deg, 120 deg
-- between neighbours, 0.5 Hz) both ways, on a flat floor, at the default settings (dt 1 ms, 20
-- iterations), dt/4, 4x the iterations and both. Drift = the sideways distance in % of the
-- distance travelled along the chain's axis.
--
--   gaitlab run bench/lua/drift.lua --no-record
--
-- DRIFT_MODULES (default "2 8 32") and DRIFT_FRICTION (default "0.3 1.0") set the grid,
-- DRIFT_CYCLES (default 5) the cycles measured, DRIFT_SETTINGS (default "default dt/4 4x ref")
-- the settings. Each run starts at time 0, settles 2 s, then measures (as
-- bench/lua/convergence.lua does); the control period stays 10 ms at every dt.
local chain_run = require "chain_run"

local function words(text)
  local out = {}
  for w in text:gmatch("%S+") do out[#out + 1] = w end
  return out
end
local function numbers(text)
  local out = {}
  for _, w in ipairs(words(text)) do
    local x = tonumber(w)
    if not x then error("drift.lua: '" .. w .. "' is not a number", 0) end
    out[#out + 1] = x
  end
  return out
end

local cycles = numbers(os.getenv("DRIFT_CYCLES") or "5")[1]
local modules_grid = numbers(os.getenv("DRIFT_MODULES") or "2 8 32")
local friction_grid = numbers(os.getenv("DRIFT_FRICTION") or "0.3 1.0")
local frequency, settle = 0.5, 2
local all_settings = {
  default = { dt = 0.001, iterations = 20 },
  ["dt/4"] = { dt = 0.00025, iterations = 20 },
  ["4x"] = { dt = 0.001, iterations = 80 },
  ref = { dt = 0.00025, iterations = 80 },
}
local settings = {}
for _, name in ipairs(words(os.getenv("DRIFT_SETTINGS") or "default dt/4 4x ref")) do
  local s = all_settings[name]
  if not s then
    error("drift.lua: unknown setting '" .. name .. "' in DRIFT_SETTINGS (expected default, "
          .. "dt/4, 4x or ref)", 0)
  end
  settings[#settings + 1] = { name = name, dt = s.dt, iterations = s.iterations }
end

-- mm per cycle along x (the chain's axis) and across (y), CPU seconds
local function run(modules, friction, phase, s)
  return chain_run{ modules = modules, connection = "pitch-pitch", friction = friction,
                    dt = s.dt, iterations = s.iterations, settle = settle, cycles = cycles,
                    frequency = frequency,
                    drive = function(robot)
                      robot:group("pitch"):drive(gaitlab.controllers.sine{
                        amplitude = 40, frequency = frequency, phase = phase })
                    end }
end

local function mark(p)
  return p < 3 and string.format("%.1f", p) or string.format("**%.1f**", p)
end

local names = {}
for i, s in ipairs(settings) do names[i] = s.name end
print(string.format("%d cycles of %g s after %g s; forward: phase +120 (towards -x), backward: "
                    .. "-120", cycles, 1 / frequency, settle))
print("| N | μ | wave | travel (mm/cycle) | drift % " .. table.concat(names, " / ")
      .. " | CPU s |")
print("|---|---|---|---|---|---|")
for _, n in ipairs(modules_grid) do
  for _, mu in ipairs(friction_grid) do
    for _, wave in ipairs{ { "forward", 120 }, { "backward", -120 } } do
      local drift, cpu, travel = {}, {}, nil
      for i, s in ipairs(settings) do
        local r = run(n, mu, wave[2], s)
        travel = travel or r.x
        drift[i] = mark(100 * math.abs(r.y) / math.abs(r.x))
        cpu[i] = string.format("%.1f", r.cpu)
      end
      print(string.format("| %d | %.1f | %s | %+.1f | %s | %s |", n, mu, wave[1], travel,
                          table.concat(drift, " / "), table.concat(cpu, " / ")))
      io.stdout:flush()
    end
  end
end
