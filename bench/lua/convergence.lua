-- Convergence and drift of the standard gaits (docs/performance.md, "Convergence"; issue 14,
-- points 2 and 3): how much a gait's per-cycle speed changes from the default settings
-- (dt 1 ms, 20 iterations) to dt/4, to 4x the iterations and to both (the converged
-- reference), and how far a planar gait drifts sideways.
--
--   gaitlab run bench/lua/convergence.lua --no-record             the tables of performance.md
--     (the grid: pp, py-roll-arc and py-wave, bench/lua/standard_gaits.lua's `names`)
--   gaitlab run bench/lua/convergence.lua --no-record GAIT N MU   one row (GAIT: pp, py-roll, py-wave, or py-roll-arc: bench/lua/standard_gaits.lua)
--
-- CONV_CYCLES (default 5) sets the cycles measured, CONV_MAX_TORQUE the servos' torque (below), CONV_MODULES (default "2 8 32") and
-- CONV_FRICTION (default "0.3 1.0") the grid, CONV_SOLVER the simulation's `solver` (default the
-- engine's, "block_nncg", which solves each robot's joints as one system, docs/architecture.md; or "pgs"),
-- CONV_NEWTON the simulation's `newton_steps` at every setting (default the engine's: 8 for a pitch-yaw chain of 13 modules or more, else 0),
-- CONV_SELF_COLLISION=1 chains whose bodies collide with each other (self_collision), CONV_RIGID=1 a rigid floor and CONV_STIFFNESS / CONV_DAMPING the compliant floor's values
-- (default the engine's floor: 3e3 N/m and 60 N s/m per contact point; bench/lua/floor_env.lua).
-- Each run starts at time 0 (the same start every time), settles (CONV_SETTLE, below), then
-- measures; the control period stays 10 ms at every dt.
--
-- CONV_MEASURE=speed prints issue 14's measure instead of the displacement vectors: the
-- per-cycle speed (the mean length of each cycle's displacement, 10 cycles unless CONV_CYCLES
-- says otherwise), for pitch-yaw gaits averaged over 5 start phases (0, 72, 144, 216 and 288 deg
-- added to every joint's phase; CONV_PHASES sets them), and the spread of the direction of
-- travel between the settings. The vectors compare where the robot went, which for a gait
-- whose heading wanders (a long pitch-yaw chain's does, from a perturbation of 1e-9 deg) is
-- the heading more than the speed. Where the starts of a row settle in two postures (the bodies'
-- mean tilt below or above 45 deg: a 32-module pitch-yaw wave upright, or lying twisted on its
-- side), two more rows compare the settings per posture; each setting's mean over the starts,
-- with its standard error and how many starts lay on their side, goes to stderr (such a row's
-- mean is a sample of the two motions' shares). CONV_CONTINUE=1: every setting's run
-- settles at the defaults and goes on from there at its own settings (sim:clone{ dt =, ... }),
-- so all four measure the motion the defaults settled into; the start's choice between two
-- motions (a long pitch-yaw wave upright or on its side) is then the defaults' at every setting
-- (docs/performance.md section 12, "A motion continued at finer settings").
local chain_run = require "chain_run"
local gaits = require "standard_gaits"

local measure = os.getenv("CONV_MEASURE") or "vector"
if measure ~= "vector" and measure ~= "speed" then
  error("CONV_MEASURE: 'vector' or 'speed' expected, got '" .. measure .. "'")
end
local cycles = tonumber(os.getenv("CONV_CYCLES") or (measure == "speed" and "10" or "5"))
local solver = os.getenv("CONV_SOLVER")
local newton = os.getenv("CONV_NEWTON") and math.tointeger(tonumber(os.getenv("CONV_NEWTON")))
if os.getenv("CONV_NEWTON") and (not newton or newton < 0) then
  error("CONV_NEWTON: a whole number of Newton steps >= 0 expected, got '"
        .. tostring(os.getenv("CONV_NEWTON")) .. "'", 0)
end
local continue = os.getenv("CONV_CONTINUE")
if continue and continue ~= "0" and continue ~= "1" then
  error("CONV_CONTINUE: 1 (each setting goes on from the state settled at the defaults) or 0 "
        .. "expected, got '" .. continue .. "'", 0)
end
continue = continue == "1"
local self_collision = os.getenv("CONV_SELF_COLLISION")
if self_collision and self_collision ~= "0" and self_collision ~= "1" then
  error("CONV_SELF_COLLISION: 1 (the chains' bodies collide with each other) or 0 expected, got '"
        .. self_collision .. "'", 0)
end
self_collision = self_collision == "1"
local frequency = 0.5
-- CONV_SETTLE (s) before measuring: 2 for the vectors (the tables of section 12 were made so),
-- 20 for issue 14's speed, the steady gait's: a 32-module pitch-yaw chain takes 10-20 s from
-- its straight start to a gait whose speed no longer depends on where it started (at the
-- defaults; at dt 0.25 ms and finer some starts of the 32-module wave hold a slower motion for
-- minutes, docs/performance.md section 12, "The slow motion is a long transient")
local settle = tonumber(os.getenv("CONV_SETTLE") or (measure == "speed" and "20" or "2"))
if not settle or settle < 0 then
  error("CONV_SETTLE: seconds >= 0 expected, got '" .. tostring(os.getenv("CONV_SETTLE")) .. "'", 0)
end
-- CONV_MAX_TORQUE (N m): the chains' modules are y1 with this servo torque instead of y1's 0.4,
-- an experiment (section 12: whether a gait the y1 servos cannot follow converges with servos
-- that can)
local module
if os.getenv("CONV_MAX_TORQUE") then
  local torque = tonumber(os.getenv("CONV_MAX_TORQUE"))
  if not torque or torque <= 0 then
    error("CONV_MAX_TORQUE: a torque in N m > 0 expected, got '" .. os.getenv("CONV_MAX_TORQUE")
          .. "'", 0)
  end
  module = gaitlab.module{ name = "y1_torque", base = "y1", max_torque = torque }
end

-- CONV_RIGID=1, CONV_STIFFNESS, CONV_DAMPING: the floor (bench/lua/floor_env.lua), by default
-- the engine's
local floor_env = require "floor_env"
local floor = floor_env("CONV", "convergence.lua")

-- the numbers of an environment variable's list ("0 72 144"): one or more finite numbers, or
-- an error naming the variable and the word
local function numbers(name, default)
  local text, out = os.getenv(name) or default, {}
  for w in text:gmatch("%S+") do
    local v = tonumber(w)
    if not v or v ~= v or math.abs(v) == math.huge then
      error(name .. ": a list of numbers expected, got '" .. w .. "' in '" .. text .. "'", 0)
    end
    out[#out + 1] = v
  end
  if #out == 0 then error(name .. ": a list of numbers expected, got '" .. text .. "'", 0) end
  return out
end

-- one run: mm per cycle along the body's axis at the start (x) and across it (y), CPU seconds
local function run(gait, modules, friction, dt, iterations, direction, start)
  return chain_run{ modules = modules, connection = gaits.connection(gait), module = module,
                    floor = floor,
                    friction = friction, dt = dt, iterations = iterations, settle = settle,
                    cycles = cycles, frequency = frequency, solver = solver,
                    newton_steps = newton, self_collision = self_collision,
                    settle_at = continue and { dt = 0.001, iterations = 20 } or nil,
                    drive = function(robot)
                      gaits.drive(robot, gait, { frequency = frequency, direction = direction,
                                                 start = start })
                    end }
end

-- change of a per-cycle displacement from `base`, in % of base's length
local function change(a, base)
  local ex, ey = a.x - base.x, a.y - base.y
  return 100 * math.sqrt(ex * ex + ey * ey) / math.sqrt(base.x * base.x + base.y * base.y)
end

local settings = {
  { name = "default", dt = 0.001, iterations = 20 },
  { name = "dt/4", dt = 0.00025, iterations = 20 },
  { name = "4x it", dt = 0.001, iterations = 80 },
  { name = "ref", dt = 0.00025, iterations = 80 },
}

local function mark(p)
  return p < 3 and string.format("%.1f", p) or string.format("**%.1f**", p)
end

local function convergence_row(gait, modules, friction)
  local r = {}
  for i, s in ipairs(settings) do r[i] = run(gait, modules, friction, s.dt, s.iterations) end
  local cells = {}
  for i = 1, #settings do cells[#cells + 1] = string.format("%+.1f / %+.1f", r[i].x, r[i].y) end
  print(string.format("| %s | %d | %.1f | %s | %s | %s | %s | %.1f / %.1f / %.1f / %.1f |", gait,
                      modules, friction, table.concat(cells, " | "), mark(change(r[2], r[1])),
                      mark(change(r[3], r[1])), mark(change(r[1], r[4])), r[1].cpu, r[2].cpu,
                      r[3].cpu, r[4].cpu))
  io.stdout:flush()
  return r
end

local modules_grid = numbers("CONV_MODULES", "2 8 32")
local friction_grid = numbers("CONV_FRICTION", "0.3 1.0")

-- issue 14's measure: per-cycle speed at each setting, averaged over the start phases
local phases_py = numbers("CONV_PHASES", "0 72 144 216 288")

local function pct(a, b) return 100 * math.abs(a - b) / b end
-- the bodies' mean tilt (deg, chain_run's r.tilt) that separates an upright chain from one
-- lying on its side
local tilt_split = 45

local function speed_row(gait, modules, friction)
  local phases = gait == "pp" and { 0 } or phases_py
  local mean, worst, turn = {}, 0, 0
  local per = {}
  for i, s in ipairs(settings) do
    mean[i], per[i] = 0, {}
    for k, start in ipairs(phases) do
      per[i][k] = run(gait, modules, friction, s.dt, s.iterations, 1, start)
      -- each run on stderr as it ends: the start phases' motions, which the mean mixes
      io.stderr:write(string.format("%s %d %.1f %s start %g: %.1f mm per cycle, tilt %.0f°, %.1f s "
                                    .. "CPU\n", gait, modules, friction, s.name, start,
                                    per[i][k].speed, per[i][k].tilt, per[i][k].cpu))
      mean[i] = mean[i] + per[i][k].speed / #phases
    end
  end
  -- a run's posture: 1 upright, 2 lying on its side (docs/performance.md section 12, "Upright
  -- or on its side")
  local function posture(run) return run.tilt < tilt_split and 1 or 2 end
  -- each setting's mean with its standard error over the starts (a row whose starts take two
  -- motions is a sample of their shares: section 12, "The 32-module wave from 40 start phases")
  if #phases > 1 then
    for i, s in ipairs(settings) do
      local sq, side = 0, 0
      for k = 1, #phases do
        sq = sq + (per[i][k].speed - mean[i]) ^ 2
        if posture(per[i][k]) == 2 then side = side + 1 end
      end
      io.stderr:write(string.format("%s %d %.1f %s: %.2f ± %.2f mm per cycle (the mean over %d "
                                    .. "starts ± its standard error), %d of them on their side\n",
                                    gait, modules, friction, s.name, mean[i],
                                    math.sqrt(sq / (#phases - 1) / #phases), #phases, side))
    end
  end
  for k = 1, #phases do
    local a, b = per[1][k], per[4][k]
    worst = math.max(worst, pct(a.speed, b.speed))
    local cos = (a.x * b.x + a.y * b.y) / math.sqrt((a.x ^ 2 + a.y ^ 2) * (b.x ^ 2 + b.y ^ 2))
    turn = math.max(turn, math.deg(math.acos(math.max(-1, math.min(1, cos)))))
  end
  print(string.format("| %s | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %s | %s | %s | %s | %.0f° |",
                      gait, modules, friction, mean[1], mean[2], mean[3], mean[4],
                      mark(pct(mean[2], mean[1])), mark(pct(mean[3], mean[1])),
                      mark(pct(mean[1], mean[4])), mark(worst), turn))
  -- where the starts took motions of two postures (a long pitch-yaw chain's wave: upright, or
  -- lying twisted on its side; docs/performance.md section 12, "Upright or on its side"), the
  -- row again per posture: each setting's mean over the starts in that posture (and how many),
  -- and the defaults' motion against the reference's in the same posture
  local seen = {}
  for i = 1, #settings do
    for k = 1, #phases do seen[posture(per[i][k])] = true end
  end
  if seen[1] and seen[2] then
    for p, name in ipairs{ "upright", "on its side" } do
      local cells, m = {}, {}
      for i = 1, #settings do
        local sum, count = 0, 0
        for k = 1, #phases do
          if posture(per[i][k]) == p then sum, count = sum + per[i][k].speed, count + 1 end
        end
        m[i] = count > 0 and sum / count or nil
        cells[i] = count > 0 and string.format("%.1f (%d)", m[i], count) or "–"
      end
      print(string.format("| %s | %d | %.1f %s | %s | %s | %s | %s | %s | %s | %s | | |", gait,
                          modules, friction, name, cells[1], cells[2], cells[3], cells[4],
                          (m[1] and m[2]) and mark(pct(m[2], m[1])) or "–",
                          (m[1] and m[3]) and mark(pct(m[3], m[1])) or "–",
                          (m[1] and m[4]) and mark(pct(m[1], m[4])) or "–"))
    end
  end
  io.stdout:flush()
end

if measure == "speed" then
  print(string.format("per-cycle speed (mm), %d cycles of %g s after %g s%s, %s; pitch-yaw: the "
                      .. "mean of start phases %s deg", cycles, 1 / frequency, settle,
                      continue and " settled at the defaults" or "",
                      floor_env.describe(floor), table.concat(phases_py, ", ")))
  print("| gait | N | μ | default (1 ms, 20 it) | dt/4 | 4× it | ref (dt/4, 4× it) | Δ dt/4 % "
        .. "| Δ 4× it % | default vs ref % | worst start phase % | heading, default vs ref |")
  print("|---|---|---|---|---|---|---|---|---|---|---|---|")
  if arg[1] then
    speed_row(arg[1], tonumber(arg[2] or "8"), tonumber(arg[3] or "0.5"))
    return
  end
  for _, gait in ipairs(gaits.names) do
    for _, n in ipairs(modules_grid) do
      for _, mu in ipairs(friction_grid) do
        speed_row(gait, n, mu)
      end
    end
  end
  return
end

local header = "| gait | N | μ | default (1 ms, 20 it) | dt/4 | 4× it | ref (dt/4, 4× it) "
    .. "| Δ dt/4 % | Δ 4× it % | default vs ref % | CPU s |"
local rule = "|---|---|---|---|---|---|---|---|---|---|---|"

if arg[1] then
  print(header)
  print(rule)
  convergence_row(arg[1], tonumber(arg[2] or "8"), tonumber(arg[3] or "0.5"))
  return
end

print(string.format("%d cycles of %g s after %g s; mm per cycle along x / across y", cycles,
                    1 / frequency, settle))
print(header)
print(rule)
local drift = {}
for _, gait in ipairs(gaits.names) do
  for _, n in ipairs(modules_grid) do
    for _, mu in ipairs(friction_grid) do
      local r = convergence_row(gait, n, mu)
      if gait == "pp" then drift[#drift + 1] = { n = n, mu = mu, forward = r } end
    end
  end
end

-- drift: the pitch-pitch wave both ways, at every setting (the forward runs are the ones above)
print()
print("| N | μ | wave | travel (mm/cycle) | drift % default / dt/4 / 4× it / ref |")
print("|---|---|---|---|---|")
for _, d in ipairs(drift) do
  local backward = {}
  for i, s in ipairs(settings) do
    backward[i] = run("pp", d.n, d.mu, s.dt, s.iterations, -1)
  end
  for _, w in ipairs{ { "forward", d.forward }, { "backward", backward } } do
    local r = w[2]
    local cells = {}
    for i = 1, #settings do
      cells[i] = mark(100 * math.abs(r[i].y) / math.abs(r[i].x))
    end
    print(string.format("| %d | %.1f | %s | %+.1f | %s |", d.n, d.mu, w[1], r[1].x,
                        table.concat(cells, " / ")))
    io.stdout:flush()
  end
end
