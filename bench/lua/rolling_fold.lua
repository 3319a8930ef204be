-- Why the 8-module pitch-yaw rolling gait folded at 90 degrees does not stop (issue 14, point 4;
-- docs/gaits.md, "rolling, at 40° and folded at 90°"). For each servo, frequency, amplitude,
-- floor friction and dt: the travel per cycle, the joints' peak angle and the fundamental of
-- their motion (amplitude and lag behind the target), the share of joint samples at the servo's
-- maximum speed, and the gap between the tail's free end and the head's free end (0 when the
-- body is a closed loop: at 90 degrees the 4 pitch joints, or the 4 yaw joints, close a square
-- of 144 mm sides).
--
--   gaitlab run bench/lua/rolling_fold.lua --no-record
--   FOLD_TABLE=solver gaitlab run bench/lua/rolling_fold.lua --no-record   (the second table only)
--   FOLD_TABLE=solver FOLD_SOLVER=block_nncg gaitlab run ...   (its block_nncg rows only)
--   FOLD_RIGID=1 FOLD_TABLE=solver gaitlab run ...   (on a rigid floor)
--   FOLD_STIFFNESS=1e4 FOLD_DAMPING=20 FOLD_TABLE=solver gaitlab run ...   (on a softer floor)
--
-- Each row is one run from time 0: one cycle to settle, then `cycles` cycles measured, sampled
-- every 10 ms (the control period, kept at every dt). Deterministic: the machine's load does not
-- change the numbers.
local cycles = tonumber(os.getenv("FOLD_CYCLES") or "10")
-- FOLD_RIGID=1: every row on a rigid floor; FOLD_STIFFNESS and FOLD_DAMPING (N/m, N s/m): on a
-- compliant floor of these instead of the engine's default one (bench/lua/floor_env.lua)
local floor_env = require "floor_env"
local floor = floor_env("FOLD", "rolling_fold.lua")

-- the servos: y1's own (docs/conventions.md), and two stiffer ones that are not y1's, to see
-- what the joints reaching 90 degrees changes
local servos = {
  { name = "y1", module = "y1" },
  { name = "kp 100", module = gaitlab.module{ name = "y1_kp100", base = "y1", kp = 100 } },
  { name = "kp 100, 1000 deg/s", module = gaitlab.module{ name = "y1_stiff", base = "y1", kp = 100, max_speed = 1000 } },
}

-- rotates v by the unit quaternion q
local function rotate(q, v)
  local tx, ty, tz = 2 * (q.y * v.z - q.z * v.y), 2 * (q.z * v.x - q.x * v.z), 2 * (q.x * v.y - q.y * v.x)
  return v.x + q.w * tx + (q.y * tz - q.z * ty), v.y + q.w * ty + (q.z * tx - q.x * tz),
         v.z + q.w * tz + (q.x * ty - q.y * tx)
end

-- distance between the tail's free end and the head's free end, m
local function end_gap(robot)
  local b = robot:bodies()
  local t, h = b[1], b[#b]
  local ax, ay, az = rotate(t.orientation, { x = -t.size.x / 2, y = 0, z = 0 })
  local bx, by, bz = rotate(h.orientation, { x = h.size.x / 2, y = 0, z = 0 })
  local dx = t.position.x + ax - h.position.x - bx
  local dy = t.position.y + ay - h.position.y - by
  local dz = t.position.z + az - h.position.z - bz
  return math.sqrt(dx * dx + dy * dy + dz * dz)
end

local function run(servo, f, amplitude, friction, dt, iterations, self_collision, solver)
  local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw", module = servo.module,
                                     self_collision = self_collision }
  local world = gaitlab.world{ floor = floor_env.on(floor, friction) }
  world:add(robot)
  robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = amplitude, frequency = f, phase = 0 })
  robot:group("yaw"):drive(gaitlab.controllers.sine{ amplitude = amplitude, frequency = f, phase = 0, phase0 = -90 })
  local every = math.floor(0.01 / dt + 0.5)
  local sim = gaitlab.simulation{ world = world, dt = dt, control_every = every, solver_iterations = iterations,
                                  solver = solver, record = false }
  local r = sim:robot("snake")
  local max_speed = (type(servo.module) == "string" and gaitlab.modules[servo.module] or servo.module).max_speed
  sim:run(1 / f)
  local p0 = r:position()
  local peak, s, c, n, fast, joints = 0, 0, 0, 0, 0, 0
  local gap_min, gap_max = math.huge, 0
  local samples = math.floor(1 / f / dt + 0.5) // every
  for _ = 1, cycles * samples do
    sim:step(every)
    local g = end_gap(r)
    gap_min, gap_max = math.min(gap_min, g), math.max(gap_max, g)
    local w = 2 * math.pi * f * sim.time
    for _, j in ipairs(r:joints()) do
      -- every joint's target is amplitude * sin(w + phase): pitch phase 0, yaw -90
      local phase = j.role == "pitch" and 0 or -math.pi / 2
      peak = math.max(peak, math.abs(j.angle))
      s = s + j.angle * math.sin(w + phase)
      c = c + j.angle * math.cos(w + phase)
      if math.abs(j.velocity) > 0.98 * max_speed then fast = fast + 1 end
      joints = joints + 1
    end
    n = n + 1
  end
  local d = r:position() - p0
  local a_s, a_c = 2 * s / joints, 2 * c / joints
  return { travel = 1000 * math.sqrt(d.x * d.x + d.y * d.y) / cycles, x = 1000 * d.x / cycles,
           y = 1000 * d.y / cycles, peak = peak, amplitude = math.sqrt(a_s * a_s + a_c * a_c),
           lag = -math.deg(math.atan(a_c, a_s)), fast = 100 * fast / joints, gap_min = 1000 * gap_min,
           gap_max = 1000 * gap_max }
end

local which = os.getenv("FOLD_TABLE")
local only = os.getenv("FOLD_SOLVER")
if only and only ~= "pgs" and only ~= "block_nncg" then
  error("rolling_fold.lua: FOLD_SOLVER must be pgs or block_nncg (got '" .. only .. "')", 0)
end
print(string.format("%d cycles after 1", cycles))
local function row(name, m)
  print(string.format("| %s | %.1f | %+.1f, %+.1f | %.1f° | %.1f°, %.1f° | %.1f %% | %.1f–%.1f |", name, m.travel, m.x, m.y,
                      m.peak, m.amplitude, m.lag, m.fast, m.gap_min, m.gap_max))
  io.stdout:flush()
end
if which ~= "solver" then
  print("| servo | f (Hz) | amplitude | floor μ | dt (ms) | travel (mm/cycle) | x, y (mm/cycle) | peak angle | fundamental, lag | at max speed | end gap (mm) |")
  print("|---|---|---|---|---|---|---|---|---|---|---|")
  for _, case in ipairs{ { servos[1], 0.5 }, { servos[1], 0.1 }, { servos[2], 0.5 }, { servos[3], 0.5 } } do
    for _, amplitude in ipairs{ 40, 90 } do
      for _, friction in ipairs{ 0.5, 1.0 } do
        for _, dt in ipairs{ 0.001, 0.00025 } do
          row(string.format("%s | %g | %d° | %.1f | %g", case[1].name, case[2], amplitude, friction, dt * 1000),
              run(case[1], case[2], amplitude, friction, dt))
        end
      end
    end
  end
end
-- the folded robot's creep against the solver (pgs, or the engine's default block_nncg, whose
-- joints are one exact system in every iteration), its iterations, dt and self-collision (its
-- free ends meet): y1, 0.1 Hz, friction 1.0. FOLD_SOLVER=block_nncg: the block_nncg rows only.
print("| amplitude | solver | solver iterations | dt (ms) | self_collision | travel (mm/cycle) | x, y (mm/cycle) | peak angle | fundamental, lag | at max speed | end gap (mm) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
local settings = { { "pgs", 20, 0.001, false }, { "pgs", 80, 0.001, false }, { "pgs", 20, 0.001, true },
                   { "block_nncg", 20, 0.001, false }, { "block_nncg", 80, 0.001, false },
                   { "block_nncg", 20, 0.00025, false }, { "block_nncg", 80, 0.00025, false } }
for _, amplitude in ipairs{ 40, 90 } do
  for _, s in ipairs(settings) do
    if not only or only == s[1] then
      row(string.format("%d° | %s | %d | %g | %s", amplitude, s[1], s[2], s[3] * 1000, tostring(s[4])),
          run(servos[1], 0.1, amplitude, 1.0, s[3], s[2], s[4], s[1]))
    end
  end
end
