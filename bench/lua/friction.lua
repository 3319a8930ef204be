-- The friction model's numerical effects (docs/performance.md, "Friction: the contact model"):
-- how much the gaits that slide on their contacts depend on dt and on the solver's iterations,
-- how far a straight gait drifts sideways, and how far an undriven robot creeps at rest.
--
--   gaitlab run bench/lua/friction.lua --no-record
--
-- Each line is one run from time 0 (the same start every time): 2 s to settle into the gait,
-- then `cycles` periods measured. The control period is kept at 10 ms whatever dt is.
local cycles = tonumber(os.getenv("FRICTION_CYCLES") or "10")

local function simulation(world, dt, iterations)
  return gaitlab.simulation{ world = world, dt = dt, control_every = math.floor(0.01 / dt + 0.5),
                             solver_iterations = iterations, record = false }
end

-- the rolling gait of an 8-module pitch-yaw robot (Gonzalez-Gomez et al., CLAWAR 2006): every
-- joint of a plane in phase, the yaw joints 90 degrees behind the pitch joints. It rolls about
-- its body axis (x) and moves sideways (y). Returns mm per cycle along y, and along x.
local function rolling(dt, iterations, friction, amplitude)
  local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
  local world = gaitlab.world{ floor = { friction = friction } }
  world:add(robot)
  local f = 0.5
  robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = amplitude, frequency = f, phase = 0 })
  robot:group("yaw"):drive(gaitlab.controllers.sine{ amplitude = amplitude, frequency = f, phase = 0,
                                                     phase0 = -90 })
  local sim = simulation(world, dt, iterations)
  local r = sim:robot("snake")
  sim:run(2)
  local p0 = r:position()
  sim:run(cycles / f)
  local d = r:position() - p0
  return 1000 * d.y / cycles, 1000 * d.x / cycles
end

-- a 2-module pitch-pitch robot's travelling wave on a flat floor: nothing pushes it sideways.
-- Returns the distance along its axis (mm per cycle) and the sideways drift in % of it.
local function pitch_pitch(dt, iterations, friction)
  local robot = gaitlab.robot.chain{ name = "inchworm", modules = 2, connection = "pitch-pitch" }
  local world = gaitlab.world{ floor = { friction = friction } }
  world:add(robot)
  local f = 0.5
  robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = f, phase = 120 })
  local sim = simulation(world, dt, iterations)
  local r = sim:robot("inchworm")
  sim:run(2)
  local p0 = r:position()
  sim:run(cycles / f)
  local d = r:position() - p0
  return 1000 * math.abs(d.x) / cycles, 100 * math.abs(d.y) / math.abs(d.x)
end

-- an undriven 8-module pitch-yaw robot left on the floor for 20 s: mm its centre of mass moves
-- along the floor after the first 0.5 s (it settles onto the floor then)
local function creep(dt, iterations, friction)
  local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
  local world = gaitlab.world{ floor = { friction = friction } }
  world:add(robot)
  local sim = simulation(world, dt, iterations)
  local r = sim:robot("snake")
  sim:run(0.5)
  local p0 = r:position()
  sim:run(20)
  local d = r:position() - p0
  return 1000 * math.sqrt(d.x * d.x + d.y * d.y)
end

print(string.format("%d cycles of 2 s after 2 s", cycles))
print("| gait | friction | dt (ms) | iterations | across (mm/cycle) | along (mm/cycle) |")
print("|---|---|---|---|---|---|")
for _, friction in ipairs{ 0.5, 1.0 } do
  for _, s in ipairs{ { 0.001, 20 }, { 0.00025, 20 }, { 0.001, 80 } } do
    local y, x = rolling(s[1], s[2], friction, 40)
    print(string.format("| rolling, 8 py, 40 deg | %.1f | %g | %d | %+.1f | %+.1f |", friction,
                        s[1] * 1000, s[2], y, x))
  end
end
for _, s in ipairs{ { 0.001, 20 }, { 0.00025, 20 } } do
  local y, x = rolling(s[1], s[2], 1.0, 90)
  print(string.format("| rolling, 8 py, 90 deg | 1.0 | %g | %d | %+.1f | %+.1f |", s[1] * 1000,
                      s[2], y, x))
end
print()
print("| gait | friction | dt (ms) | iterations | travel (mm/cycle) | drift (% of travel) |")
print("|---|---|---|---|---|---|")
for _, friction in ipairs{ 0.5, 1.0 } do
  for _, s in ipairs{ { 0.001, 20 }, { 0.00025, 20 }, { 0.001, 80 } } do
    local x, drift = pitch_pitch(s[1], s[2], friction)
    print(string.format("| 2 pp, 40 deg | %.1f | %g | %d | %.1f | %.1f |", friction, s[1] * 1000,
                        s[2], x, drift))
  end
end
print()
for _, friction in ipairs{ 0.5, 1.0 } do
  print(string.format("creep of an undriven 8 py at rest, friction %.1f: %.4f mm in 20 s", friction,
                      creep(0.001, 20, friction)))
end
