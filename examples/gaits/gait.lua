-- The gait gallery's measuring code (docs/gaits.md): builds a chain robot, drives its joint groups
-- with sine generators, lets the gait settle, then measures it cycle by cycle and prints what it
-- measured beside what the paper reports. Every example of examples/gaits/ requires it:
--
--   local gait = require "gait"   (found beside the requiring script)
--   return gait.run{ name = ..., modules = ..., connection = ..., groups = { ... }, paper = { ... } }
--
-- What it measures, per cycle of the sine (T = 1 / frequency), averaged over `cycles` cycles
-- that start after `settle` cycles:
--   along   centre-of-mass displacement along the body (the tail->head direction at the start of
--           each cycle, robot:heading()), mm/cycle; positive head first
--   across  the same, across the body, mm/cycle; positive to the robot's left
--   speed   |displacement| / cycle, also in mm/s
--   turn    robot:turned() per cycle, deg/cycle; positive counter-clockwise seen from above
--   roll    rotation of the tail body about its own long axis (x), deg/cycle; positive
--           counter-clockwise seen from the head (as a positive roll angle, docs/conventions.md)
local gait = {}

-- set by a caller before it runs an example (tests/gaits/check.lua, tools/gait_pictures.lua):
--   cycles, settle  override the gait's own numbers of cycles
--   reverse         every sine's phase and phase0 negated: the same joint motion played backwards
--                   in time (sin(wt + p) at -t is sin(wt - p + 180))
--   record          a folder: each gait is recorded into FOLDER/NAME (NAME the gait's name)
--   quiet           print nothing
gait.options = { cycles = nil, settle = nil, reverse = false, record = nil, quiet = false }

local KEYS = { name = true, modules = true, connection = true, friction = true, groups = true,
               cycles = true, settle = true, paper = true, dt = true, control_every = true,
               floor = true }
local SINE = { amplitude = true, frequency = true, phase = true, phase0 = true, offset = true }

local function check(spec)
  for k in pairs(spec) do
    if not KEYS[k] then error(string.format("gait.run: unknown key '%s'", k), 3) end
  end
  if spec.cycles ~= nil and (math.type(spec.cycles) ~= "integer" or spec.cycles < 1) then
    error(string.format("gait.run: cycles must be an integer of at least 1 (got %s)", tostring(spec.cycles)), 3)
  end
  if spec.settle ~= nil and (math.type(spec.settle) ~= "integer" or spec.settle < 0) then
    error(string.format("gait.run: settle must be an integer number of cycles, 0 or more (got %s)",
                        tostring(spec.settle)), 3)
  end
  if type(spec.name) ~= "string" then error("gait.run: 'name' must be a string", 3) end
  if spec.floor ~= nil and (type(spec.floor) ~= "table" or spec.floor.friction ~= nil) then
    error("gait.run: 'floor' must be a table of the floor's other keys (rigid, stiffness, damping: "
          .. "docs/lua-api.md); its friction is the key 'friction'", 3)
  end
  if type(spec.groups) ~= "table" or next(spec.groups) == nil then
    error("gait.run: 'groups' must map a joint group (\"pitch\", \"yaw\", \"all\") to sine parameters", 3)
  end
  for group, p in pairs(spec.groups) do
    for k in pairs(p) do
      if not SINE[k] then
        error(string.format("gait.run: groups.%s: unknown sine parameter '%s'", group, k), 3)
      end
    end
  end
end

-- the frequency every group shares (a gait has one period)
local function frequency_of(groups)
  local f
  for group, p in pairs(groups) do
    local g = p.frequency or 0.5
    if f and math.abs(f - g) > 1e-12 then
      error(string.format("gait.run: groups.%s: every group must share one frequency (%g and %g)",
                          group, f, g), 3)
    end
    f = g
  end
  if not (f > 0) then error("gait.run: the frequency must be above 0 Hz (a gait needs a period)", 3) end
  return f
end

-- the tail body's roll about its own x axis, radians in (-pi, pi]
local function roll_of(robot)
  local q = robot:bodies()[1].orientation
  return math.atan(2 * (q.y * q.z + q.w * q.x), 1 - 2 * (q.x * q.x + q.y * q.y))
end

-- calls gaitlab's constructor f(...); its error, if any, is raised again from the caller of
-- gait.run (level 3 from here) with what was being built
local function build(what, f, ...)
  local ok, result = pcall(f, ...)
  if not ok then
    local message = tostring(result):gsub("^[^:]*:%d+: ", "")
    message = message:match("^bad argument #%d+ to '[^']*' %((.*)%)$") or message
    error(string.format("gait.run: %s: %s", what, message), 3)
  end
  return result
end

local function wrap(a)
  while a > math.pi do a = a - 2 * math.pi end
  while a <= -math.pi do a = a + 2 * math.pi end
  return a
end

-- Builds and runs one gait; returns the measurement (see the top of this file) and prints it with
-- the paper's report unless gait.options.quiet.
function gait.run(spec)
  check(spec)
  local o = gait.options
  local f = frequency_of(spec.groups)
  local period = 1 / f
  local cycles = o.cycles or spec.cycles or 10
  local settle = o.settle or spec.settle or 1
  if math.type(cycles) ~= "integer" or cycles < 1 then
    error(string.format("gait.run: gait.options.cycles must be an integer of at least 1 (got %s)", tostring(cycles)), 2)
  end
  if math.type(settle) ~= "integer" or settle < 0 then
    error(string.format("gait.run: gait.options.settle must be an integer number of cycles, 0 or more (got %s)",
                        tostring(settle)), 2)
  end
  local robot = build("robot", gaitlab.robot.chain, { name = spec.name, modules = spec.modules,
                                                     connection = spec.connection or "pitch-pitch" })
  local floor = { friction = spec.friction or 1.0 }
  for k, v in pairs(spec.floor or {}) do floor[k] = v end
  local world = build("world", gaitlab.world, { floor = floor })
  world:add(robot)
  local order = {}
  for group in pairs(spec.groups) do order[#order + 1] = group end
  table.sort(order)
  local params = {}
  for _, group in ipairs(order) do
    local p = {}
    for k, v in pairs(spec.groups[group]) do p[k] = v end
    if o.reverse then
      p.phase = -(p.phase or 120)
      p.phase0 = -(p.phase0 or 0)
    end
    params[group] = p
    local g = build("groups." .. group, robot.group, robot, group)
    g:drive(build("groups." .. group, gaitlab.controllers.sine, p))
  end
  local sim = build("simulation", gaitlab.simulation, {
    world = world, dt = spec.dt, control_every = spec.control_every or 10,
    record = o.record and (o.record .. "/" .. spec.name) or nil })
  local r = sim:robot(spec.name)
  sim:run(settle * period)

  -- sample the roll often enough to unwrap it (a few degrees a sample at most)
  local samples = math.max(1, math.floor(period / sim.dt / 100 + 0.5))
  local steps = math.floor(period / sim.dt + 0.5)
  local along, across, turn, roll = 0, 0, 0, 0
  local path = { { x = r:position().x, y = r:position().y } }
  local last_roll = roll_of(r)
  for _ = 1, cycles do
    local p0, h0, t0 = r:position(), math.rad(r:heading()), r:turned()
    local done = 0
    while done < steps do
      local n = math.min(samples, steps - done)
      sim:step(n)
      done = done + n
      local now = roll_of(r)
      roll = roll + wrap(now - last_roll)
      last_roll = now
    end
    local d = r:position() - p0
    along = along + d.x * math.cos(h0) + d.y * math.sin(h0)
    across = across - d.x * math.sin(h0) + d.y * math.cos(h0)
    turn = turn + (r:turned() - t0)
    path[#path + 1] = { x = r:position().x, y = r:position().y }
  end
  local total = path[#path]
  local dx, dy = total.x - path[1].x, total.y - path[1].y
  local m = {
    name = spec.name, cycles = cycles, frequency = f, reversed = o.reverse,
    along = 1000 * along / cycles, across = 1000 * across / cycles,
    speed = 1000 * math.sqrt(dx * dx + dy * dy) / cycles,
    turn = turn / cycles, roll = math.deg(roll) / cycles, path = path, sim = sim, robot = r,
    params = params, floor = floor,
  }
  if not o.quiet then gait.print(spec, m) end
  return m
end

local function describe(params)
  local parts = {}
  local order = {}
  for group in pairs(params) do order[#order + 1] = group end
  table.sort(order)
  for _, group in ipairs(order) do
    local p = params[group]
    parts[#parts + 1] = string.format("%s: A %g deg, phase %g, phase0 %g, offset %g", group,
                                      p.amplitude or 40, p.phase or 120, p.phase0 or 0, p.offset or 0)
  end
  return table.concat(parts, "; ")
end

-- what the paper says beside a measured number: its value, or that it gives none
local function reported(paper, key, unit)
  local v = paper and paper[key]
  if v == nil then return "no number in the source" end
  if type(v) == "number" then return string.format("%g %s", v, unit) end
  return tostring(v)
end

-- the floor of a spec's `floor` keys in words, nil for the engine's default floor
function gait.floor_text(f)
  f = f or {}
  if f.rigid then return "a rigid floor" end
  if not (f.stiffness or f.damping) then return nil end
  return string.format("a floor of stiffness %s, damping %s",
                       f.stiffness and string.format("%g N/m", f.stiffness) or "the default",
                       f.damping and string.format("%g N s/m", f.damping) or "the default")
end

function gait.print(spec, m)
  local paper = spec.paper or {}
  local text = gait.floor_text(spec.floor)
  local floor = text and " (" .. text .. ")" or ""
  print(string.format("%s: %d modules %s, friction %.1f%s, %g Hz%s", spec.name, spec.modules,
                      spec.connection or "pitch-pitch", spec.friction or 1.0, floor, m.frequency,
                      m.reversed and ", reversed" or ""))
  print("  " .. describe(m.params))
  print(string.format("  measured over %d cycles after %d:", m.cycles, gait.options.settle or spec.settle or 1))
  print(string.format("  | %-28s | %-22s | %s", "quantity", "measured", "paper reports"))
  local rows = {
    { "along the body (mm/cycle)", string.format("%+.1f (%+.1f mm/s)", m.along, m.along * m.frequency), reported(paper, "along", "mm/cycle") },
    { "across the body (mm/cycle)", string.format("%+.1f (%+.1f mm/s)", m.across, m.across * m.frequency), reported(paper, "across", "mm/cycle") },
    { "turning (deg/cycle)", string.format("%+.1f", m.turn), reported(paper, "turn", "deg/cycle") },
    { "roll (deg/cycle)", string.format("%+.1f", m.roll), reported(paper, "roll", "deg/cycle") },
  }
  for _, row in ipairs(rows) do print(string.format("  | %-28s | %-22s | %s", row[1], row[2], row[3])) end
  if paper.source then print("  paper: " .. paper.source) end
  if paper.outcome then print("  the paper's outcome: " .. paper.outcome) end
end

return gait
