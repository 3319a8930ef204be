-- The steady per-cycle speed of a standard gait, start phase by start phase (docs/performance.md,
-- section 12, "The slow motion is a long transient" and "block_nncg the default"): a long
-- chain settles for 10-20 s from its straight start, and some settings and starts hold a slower
-- motion for minutes before they leave it, so the speed of one stretch of cycles can belong to
-- either. This prints the speed of every block of cycles from time 0, then the mean of the last
-- blocks, per start and over the starts.
--
--   gaitlab run bench/lua/steady_speed.lua --no-record GAIT N MU [DT_MS ITERATIONS [SOLVER]]
--
-- GAIT: pp, py-roll, py-wave or py-roll-arc (bench/lua/standard_gaits.lua); N modules; MU the floor's
-- friction; DT_MS the step in ms and ITERATIONS the solver's (default 1 and 20, the engine's);
-- SOLVER "block_nncg" or "pgs" (default the engine's). The controllers run every 10 ms at
-- every dt. STEADY_PHASES (default "0 72 144 216 288") the start phases in degrees, added to
-- every joint's phase; STEADY_BLOCKS (default 12) blocks of STEADY_CYCLES (default 5) cycles of
-- 2 s; STEADY_LAST (default 6) the blocks averaged at the end; STEADY_MAX_TORQUE (N m) makes the
-- modules y1 with this servo torque instead of y1's 0.4 (an experiment: a gait the y1 servos
-- cannot follow, with servos that can); STEADY_RIGID=1 a rigid floor, STEADY_STIFFNESS and
-- STEADY_DAMPING (N/m, N s/m) the compliant floor's values instead of the engine's defaults
-- (bench/lua/floor_env.lua; gaitlab.world's floor keys, docs/lua-api.md); STEADY_NEWTON=K the
-- simulation's newton_steps (default the engine's: 8 for a pitch-yaw chain of 13 modules or
-- more, else 0); STEADY_SELF_COLLISION=1 a chain whose bodies collide with each other
-- (self_collision). The speed of a block
-- is the mean length of its cycles' displacements of the centre of mass, in mm per cycle.
--
-- STEADY_MOTION=1 also prints, per start, what motion the last blocks are (docs/performance.md,
-- section 12, "Two rows looked at closer"): the speed to 0.01 mm; the net travel
-- per cycle; the direction of travel against the body's axis (tail to head, -90: sideways to the
-- right); the turn of that axis per cycle; the head-to-tail distance; the highest mean height of
-- the bodies; and the centre's horizontal path per cycle, sampled every 10 ms (the to and fro a
-- small net travel is the rest of). It samples the bodies every 10 ms, which leaves the
-- trajectory as it is (the same steps, run in pieces).
--
-- STEADY_POSTURE=1 prints each block as speed/tilt: the bodies' mean tilt in degrees (0
-- upright, 90 on their side, 180 upside down), sampled every 0.1 s, which tells a long
-- pitch-yaw chain's two wave motions apart (docs/performance.md, section 12, "Upright or on its
-- side"); the same pieces, the same trajectory.
--
-- STEADY_CHECK=SECONDS runs, for each start, the engine's accuracy check instead
-- (sim:check_accuracy, docs/lua-api.md; STEADY_SETTLE its settling time, default 0): the gait
-- for SECONDS from time 0 at the given settings, at dt/4 and at 4x the iterations, and prints
-- each run's path sampled once per cycle, the given one's in % off the finer ones', with the
-- warnings the check gives.
local gaits = require "standard_gaits"

local function fail(message) error("steady_speed.lua: " .. message, 0) end

local function count(name, default, min)
  local text = os.getenv(name)
  if not text then return default end
  local n = math.tointeger(tonumber(text))
  if not n or n < min then
    fail(string.format("%s: a whole number >= %d expected, got '%s'", name, min, text))
  end
  return n
end

local gait, modules, friction = arg[1], math.tointeger(tonumber(arg[2] or "")), tonumber(arg[3] or "")
if not gait or not arg[3] then
  fail("usage: gaitlab run bench/lua/steady_speed.lua --no-record GAIT N MU [DT_MS ITERATIONS [SOLVER]]")
end
if not gaits.is_known(gait) then
  fail("GAIT: " .. gaits.listed() .. " expected, got '" .. gait .. "'")
end
if not modules or modules < 2 then fail("N: a whole number of modules >= 2 expected, got '" .. arg[2] .. "'") end
if not friction or friction < 0 then fail("MU: a friction >= 0 expected, got '" .. arg[3] .. "'") end
local dt_ms = tonumber(arg[4] or "1")
if not dt_ms or dt_ms <= 0 or dt_ms > 10 then fail("DT_MS: a step in (0, 10] ms expected, got '" .. arg[4] .. "'") end
local iterations = math.tointeger(tonumber(arg[5] or "20"))
if not iterations or iterations < 1 then fail("ITERATIONS: a whole number >= 1 expected, got '" .. arg[5] .. "'") end
local solver = arg[6]
local newton = count("STEADY_NEWTON", nil, 0)
local self_collision = os.getenv("STEADY_SELF_COLLISION")
if self_collision and self_collision ~= "0" and self_collision ~= "1" then
  fail("STEADY_SELF_COLLISION: 1 (the chain's bodies collide with each other) or 0 expected, got '"
       .. self_collision .. "'")
end
self_collision = self_collision == "1"
if solver and solver ~= "pgs" and solver ~= "block_nncg" then
  fail("SOLVER: pgs or block_nncg expected, got '" .. solver .. "'")
end

local phases = {}
for w in (os.getenv("STEADY_PHASES") or "0 72 144 216 288"):gmatch("%S+") do
  local p = tonumber(w)
  if not p then fail("STEADY_PHASES: start phases in degrees expected, got '" .. w .. "'") end
  phases[#phases + 1] = p
end
if #phases == 0 then fail("STEADY_PHASES: at least one start phase expected") end
local blocks = count("STEADY_BLOCKS", 12, 1)
local per_block = count("STEADY_CYCLES", 5, 1)
local last = count("STEADY_LAST", 6, 1)
if last > blocks then
  fail(string.format("STEADY_LAST (%d) must be at most STEADY_BLOCKS (%d)", last, blocks))
end

local module
if os.getenv("STEADY_MAX_TORQUE") then
  local torque = tonumber(os.getenv("STEADY_MAX_TORQUE"))
  if not torque or torque <= 0 or torque == math.huge then
    fail("STEADY_MAX_TORQUE: a torque in N m > 0 expected, got '" .. os.getenv("STEADY_MAX_TORQUE") .. "'")
  end
  module = gaitlab.module{ name = "y1_torque", base = "y1", max_torque = torque }
end

local floor_env = require "floor_env"
local floor = floor_env("STEADY", "steady_speed.lua")

local motion = os.getenv("STEADY_MOTION")
if motion ~= nil and motion ~= "0" and motion ~= "1" then
  fail("STEADY_MOTION: 1 (describe each start's motion) or 0 expected, got '" .. motion .. "'")
end
motion = motion == "1"
local posture = os.getenv("STEADY_POSTURE")
if posture ~= nil and posture ~= "0" and posture ~= "1" then
  fail("STEADY_POSTURE: 1 (each block's tilt) or 0 expected, got '" .. posture .. "'")
end
posture = posture == "1"

local check = os.getenv("STEADY_CHECK")
if check ~= nil then
  local seconds = tonumber(check)
  if not seconds or not (seconds > 0 and seconds <= 3600) then
    fail("STEADY_CHECK: the check's seconds in (0, 3600] expected, got '" .. check .. "'")
  end
  check = seconds
end
-- STEADY_SETTLE: the check's settling time, s (default 0)
local check_settle = tonumber(os.getenv("STEADY_SETTLE") or "0")
if not check_settle or not (check_settle >= 0) or (check and check_settle >= check) then
  fail("STEADY_SETTLE: seconds in [0, STEADY_CHECK) expected, got '" .. os.getenv("STEADY_SETTLE") .. "'")
end

local frequency = 0.5
local dt = dt_ms / 1000
local every = math.max(1, math.floor(0.01 / dt + 0.5))

local function wrap(radians) return (radians + math.pi) % (2 * math.pi) - math.pi end
local function horizontal(d) return math.sqrt(d.x ^ 2 + d.y ^ 2) end

-- STEADY_MOTION: the sums over the measured cycles that describe_motion turns into a line
local function motion_sums()
  return { cycles = 0, travel = 0, turn = 0, length = 0, height = 0, path = 0, tilt = 0,
           samples = 0 }
end

-- the bodies' mean tilt, degrees
local tilt = require "posture"

-- the robot's axis (tail to head): its heading in the plane and its length
local function axis(robot)
  local bodies = robot:bodies()
  local d = bodies[#bodies].position - bodies[1].position
  return math.atan(d.y, d.x), math.sqrt(d.x ^ 2 + d.y ^ 2 + d.z ^ 2)
end

-- one cycle, sampled every 10 ms into `sums` (a measured cycle) or not (nil)
local function sampled_cycle(sim, robot, sums)
  local heading0 = axis(robot)
  local from = robot:position()
  local last = from
  for _ = 1, math.floor(100 / frequency + 0.5) do
    sim:run(0.01)
    local now, z = robot:position(), 0
    local bodies = robot:bodies()
    for _, b in ipairs(bodies) do z = z + b.position.z end
    sums.height = math.max(sums.height, z / #bodies)
    sums.path = sums.path + horizontal(now - last)
    sums.tilt = sums.tilt + tilt(robot)
    sums.samples = sums.samples + 1
    last = now
  end
  local heading, length = axis(robot)
  local d = last - from
  sums.cycles = sums.cycles + 1
  sums.travel = sums.travel + wrap(math.atan(d.y, d.x) - heading)
  sums.turn = sums.turn + wrap(heading - heading0)
  sums.length = sums.length + length
end

-- `speed`: the measured blocks' mean speed (mm per cycle), `net`: their net travel (m)
local function describe_motion(sums, speed, net)
  local n = sums.cycles
  return string.format("speed %.2f mm/cycle, net %.2f, travel %+.0f deg from the axis, turn %+.1f deg/cycle, "
                       .. "head to tail %.0f mm, highest mean height %.1f mm, path %.2f mm/cycle, "
                       .. "tilt %.0f deg",
                       speed, 1000 * net / n, math.deg(sums.travel / n),
                       math.deg(sums.turn / n), 1000 * sums.length / n, 1000 * sums.height,
                       1000 * sums.path / n, sums.tilt / sums.samples)
end

-- the gait from phase `start` at time 0: its simulation and robot
local function build(start)
  local robot = gaitlab.robot.chain{ name = "snake", modules = modules, module = module,
                                     connection = gaits.connection(gait),
                                     self_collision = self_collision }
  local world = gaitlab.world{ floor = floor_env.on(floor, friction) }
  world:add(robot)
  gaits.drive(robot, gait, { frequency = frequency, start = start })
  return gaitlab.simulation{ world = world, dt = dt, control_every = every,
                             solver_iterations = iterations, solver = solver,
                             newton_steps = newton, record = false },
         robot
end

-- the speed of each block, mm per cycle; with STEADY_MOTION the last blocks' motion sums and
-- net travel (m); with STEADY_POSTURE each block's mean tilt (deg)
local function run(start)
  local sim, robot = build(start)
  local speeds, tilts, before = {}, {}, robot:position()
  local sums, measured_from = motion_sums(), nil
  for b = 1, blocks do
    local length, tilt_sum = 0, 0
    if b == blocks - last + 1 then measured_from = robot:position() end
    for _ = 1, per_block do
      if motion and b > blocks - last then
        sampled_cycle(sim, robot, sums)
      elseif posture then
        for _ = 1, 20 do
          sim:run(0.05 / frequency)
          tilt_sum = tilt_sum + tilt(robot)
        end
      else
        sim:run(1 / frequency)
      end
      local now = robot:position()
      length = length + horizontal(now - before)
      before = now
    end
    speeds[b] = 1000 * length / per_block
    tilts[b] = tilt_sum / (20 * per_block)
  end
  return speeds, sim.solver, sums, motion and horizontal(robot:position() - measured_from), tilts
end

-- STEADY_CHECK: the engine's accuracy check (sim:check_accuracy) of each start instead
if check then
  local worst = { dt = 0, iterations = 0 }
  for _, start in ipairs(phases) do
    local r = build(start):check_accuracy{ seconds = check, cycle = 1 / frequency,
                                          settle = check_settle }.robots[1]
    print(string.format("start %g deg: path %.1f mm; dt/4 %.1f mm (%+.1f %%), 4x iterations %.1f mm (%+.1f %%)",
                        start, 1000 * r.given.path, 1000 * r.dt.path, r.dt_off,
                        1000 * r.iterations.path, r.iterations_off))
    worst.dt = math.max(worst.dt, math.abs(r.dt_off))
    worst.iterations = math.max(worst.iterations, math.abs(r.iterations_off))
    io.stdout:flush()
  end
  print(string.format("%s N %d mu %g, dt %g ms, %d iterations, %s: the check from %g to %g s, worst of %d starts: dt/4 %.1f %%, 4x iterations %.1f %%",
                      gait, modules, friction, dt_ms, iterations, floor_env.describe(floor),
                      check_settle, check, #phases, worst.dt, worst.iterations))
  return
end

local total, used = 0, nil
for _, start in ipairs(phases) do
  local speeds, name, sums, net, tilts = run(start)
  used = name
  local sum, cells = 0, {}
  for b, v in ipairs(speeds) do
    cells[b] = posture and string.format("%.1f/%.0f", v, tilts[b]) or string.format("%.1f", v)
    if b > blocks - last then sum = sum + v end
  end
  local mean = sum / last
  total = total + mean
  print(string.format("start %g deg: %s | last %d blocks %.1f", start, table.concat(cells, " "), last, mean))
  if motion then
    print(string.format("start %g deg, last %d blocks: %s", start, last, describe_motion(sums, mean, net)))
  end
  io.stdout:flush()
end
print(string.format("%s N %d mu %g, dt %g ms, %d iterations, %s, %s, blocks of %d cycles: mean over %d starts %.1f mm per cycle",
                    gait, modules, friction, dt_ms, iterations, used, floor_env.describe(floor),
                    per_block, #phases, total / #phases))
if motion then
  print(string.format("mean speed over %d starts, last %d blocks: %.3f mm per cycle", #phases, last,
                      total / #phases))
end
