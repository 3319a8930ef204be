-- Whether a robot's servos can follow a standard gait (docs/performance.md, section 12, "The
-- rows not met"): per cycle, how far the joints are from their targets and how often a servo
-- gives its maximum torque, with the robot's per-cycle speed.
--
--   gaitlab run bench/lua/servo_load.lua --no-record GAIT N MU [CYCLES]
--
-- GAIT: pp, py-roll or py-wave (bench/lua/standard_gaits.lua); defaults py-roll 32 1.0, 10
-- cycles of 2 s from time 0 at the engine's defaults (dt 1 ms, 20 iterations). SERVO_SOLVER sets
-- the simulation's solver, SERVO_START the start phase (deg, added to every joint),
-- SERVO_MAX_TORQUE (N m) the modules' servo torque (y1 with that torque instead of 0.4, an
-- experiment). The joints are sampled every 50 ms; "at max torque" counts the samples where a
-- joint's torque is 98 % of the servo's maximum or more.
local gaits = require "standard_gaits"

local gait = arg[1] or "py-roll"
local modules = tonumber(arg[2] or "32")
local friction = tonumber(arg[3] or "1.0")
local cycles = tonumber(arg[4] or "10")
if not modules or not friction or not cycles then
  error("servo_load.lua: GAIT N MU [CYCLES] expected (numbers for N, MU and CYCLES)", 0)
end
local max_torque = 0.4  -- y1's (docs/modules.md)
local module
if os.getenv("SERVO_MAX_TORQUE") then
  max_torque = tonumber(os.getenv("SERVO_MAX_TORQUE"))
  if not max_torque or max_torque <= 0 then
    error("SERVO_MAX_TORQUE: a torque in N m > 0 expected, got '"
          .. os.getenv("SERVO_MAX_TORQUE") .. "'", 0)
  end
  module = gaitlab.module{ name = "y1_torque", base = "y1", max_torque = max_torque }
end

local robot = gaitlab.robot.chain{ name = "snake", modules = modules,
                                   connection = gaits.connection(gait), module = module }
local world = gaitlab.world{ floor = { friction = friction } }
world:add(robot)
gaits.drive(robot, gait, { frequency = 0.5, start = tonumber(os.getenv("SERVO_START") or "0") })
local sim = gaitlab.simulation{ world = world, solver = os.getenv("SERVO_SOLVER"), record = false }
local r = sim:robot("snake")

print(string.format("%s, %d modules, friction %.1f, servo %.2f N m, solver %s, start %s deg", gait,
                    modules, friction, max_torque, os.getenv("SERVO_SOLVER") or "pgs",
                    os.getenv("SERVO_START") or "0"))
print("| cycle | tracking error: largest, mean | samples at max torque | displacement (mm) |")
print("|---|---|---|---|")
local last = r:position()
for c = 1, cycles do
  local worst, sum, n, at_max = 0, 0, 0, 0
  for _ = 1, 40 do
    sim:run(0.05)
    for _, j in ipairs(r:joints()) do
      local e = math.abs(j.angle - j.target)
      worst, sum, n = math.max(worst, e), sum + e, n + 1
      if math.abs(j.torque) >= 0.98 * max_torque then at_max = at_max + 1 end
    end
  end
  local p = r:position()
  print(string.format("| %d | %.1f°, %.1f° | %.1f %% | %.1f |", c, worst, sum / n, 100 * at_max / n,
                      1000 * math.sqrt((p.x - last.x) ^ 2 + (p.y - last.y) ^ 2)))
  io.stdout:flush()
  last = p
end
