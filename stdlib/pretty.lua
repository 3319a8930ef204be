-- gaitlab.pretty(value [, { depth =, items =, width = }]): a value as the console prints it.
-- Tables are shown nested with their keys sorted (numbers, then strings, then the rest), arrays
-- compactly, a table inside itself as <cycle>, and within limits (depth, entries per table, and
-- a total for the whole value) so that a huge or deeply shared table never floods the terminal
-- or hangs it. gaitlab objects (robots, controllers, simulations, ...) are described: what they
-- are, their state, their parameters.
local gaitlab = ...
local type, next, pairs, ipairs, tostring, pcall = type, next, pairs, ipairs, tostring, pcall
local rawget, rawlen, getmetatable = rawget, rawlen, getmetatable
local format, concat, sort, rep = string.format, table.concat, table.sort, string.rep
local math_type, huge = math.type, math.huge

local defaults = { depth = 4, items = 40, width = 78, total = 400 }
-- keys looked at in one table at most: beyond, the table is shown as the first of them
local kMaxKeys = 10000

local keywords = {}
for w in ([[and break do else elseif end false for function goto if in local nil not or
  repeat return then true until while]]):gmatch("%a+") do keywords[w] = true end

local function is_name(s)
  return type(s) == "string" and s:match("^[%a_][%w_]*$") ~= nil and not keywords[s]
end

-- a string as Lua source would write it, control characters escaped
local function quote(s)
  local escaped = s:gsub('[%c"\\\128-\255]', function(c)
    if c == "\n" then return "\\n" end
    if c == "\t" then return "\\t" end
    if c == "\r" then return "\\r" end
    if c == '"' or c == "\\" then return "\\" .. c end
    if c:byte() >= 128 then return c end
    return format("\\%d", c:byte())
  end)
  return '"' .. escaped .. '"'
end

local function number(n)
  if math_type(n) == "integer" then return tostring(n) end
  if n ~= n then return "nan" end
  if n == huge then return "math.huge" end
  if n == -huge then return "-math.huge" end
  return tostring(n)
end

-- the __name a metatable gives (gaitlab objects keep their metatable private: getmetatable
-- returns their type name)
local function type_name(v)
  local mt = getmetatable(v)
  if type(mt) == "string" then return mt end
  if type(mt) == "table" then
    local name = rawget(mt, "__name")
    if type(name) == "string" then return name end
  end
  return nil
end

-- what tostring gives, at most 4096 bytes of it; a __tostring that fails says why
local function safe_tostring(v)
  local ok, s = pcall(tostring, v)
  if not ok then
    return format("<%s: __tostring failed: %s>", type(v), type(s) == "string" and s or type(s))
  end
  if type(s) ~= "string" then return "<" .. type(v) .. ">" end
  if #s > 4096 then return s:sub(1, 4096) .. format("... (%d more bytes)", #s - 4096) end
  return s
end

local describe = {}

-- an angle in 7 columns ("°" is one column, two bytes)
local function angle(x) return x and format("%6.1f°", x) or "      -" end
-- a quantity as people write it: 30, 0.5, 1e-06
local function quantity(x) return format("%.6g", x) end

describe["gaitlab.Robot"] = function(robot)
  local lines = {}
  local chain = robot.chain
  if chain then
    lines[1] = format("robot '%s': %d %s modules, %s", robot.name, chain.modules, chain.module,
      chain.connection)
  else
    lines[1] = format("robot '%s': %d joints", robot.name, #robot)
  end
  local ok, p = pcall(robot.position, robot)
  if ok then
    lines[#lines + 1] = format("  position  x %.3f  y %.3f  z %.3f m (centre of mass)", p.x, p.y,
      p.z)
    local okh, h = pcall(function() return robot:heading() end)
    if okh and type(h) == "number" then
      lines[#lines + 1] = format("  heading   %.1f°", h)
    end
  else
    lines[#lines + 1] = "  not in a simulation yet (no pose)"
  end
  local joints = robot:joints()
  lines[#lines + 1] = format("  %5s  %-12s  %-6s  %7s  %7s   %s", "joint", "name", "role", "angle",
    "target", "range")
  for i, j in ipairs(joints) do
    if i > 24 then
      lines[#lines + 1] = format("  ... (%d more joints)", #joints - 24)
      break
    end
    lines[#lines + 1] = format("  %5d  %-12s  %-6s  %s  %s   %s° .. %s°", j.index, j.name, j.role,
      angle(j.angle), angle(j.target), quantity(j.min), quantity(j.max))
  end
  return concat(lines, "\n")
end

describe["gaitlab.Controller"] = function(ctl)
  local params = ctl:params()
  local names = {}
  for name in pairs(params) do names[#names + 1] = name end
  sort(names)
  local lines = { format("controller '%s'%s", ctl.name,
    ctl.failed and (" (failed: " .. tostring(ctl.error) .. ")") or "") }
  local width = 4
  for _, n in ipairs(names) do width = math.max(width, #n) end
  for _, n in ipairs(names) do
    local p = params[n]
    lines[#lines + 1] = format("  %-" .. width .. "s = %-10s %-5s range %s .. %s, default %s", n,
      quantity(p.value), p.unit, quantity(p.min), quantity(p.max), quantity(p.default))
  end
  if #names == 0 then lines[#lines + 1] = "  (no parameters)" end
  return concat(lines, "\n")
end

describe["gaitlab.Simulation"] = function(sim)
  local lines = { format("simulation: t = %.3f s (%d ticks of %g s, controllers every %d)",
    sim.time, sim.ticks, sim.dt, sim.control_every) }
  local dir = sim.record_dir
  lines[#lines + 1] = "  recording " .. (dir and dir or "off")
  if sim.paused then lines[#lines + 1] = "  paused (a controller failed)" end
  for _, w in ipairs(sim.warnings) do lines[#lines + 1] = "  warning: " .. w end
  return concat(lines, "\n")
end

describe["gaitlab.Group"] = function(group)
  local joints = group:joints()
  local list = {}
  for i, j in ipairs(joints) do list[i] = tostring(j) end
  return format("group of %d joints: %s", #joints, concat(list, ", "))
end

local function render(v, opts, depth, path, budget, indent)
  local t = type(v)
  if t == "string" then
    if depth == 0 then return v end  -- as lua.c prints it
    if #v > 2000 then return quote(v:sub(1, 2000)) .. format("... (%d bytes)", #v) end
    return quote(v)
  end
  if t == "number" then return number(v) end
  if t ~= "table" then
    local name = type_name(v)
    local d = name and describe[name]
    if d and depth == 0 then
      local ok, s = pcall(d, v)
      if ok and type(s) == "string" then return s end
    end
    return safe_tostring(v)
  end
  local mt = getmetatable(v)
  if mt ~= nil and (type(mt) ~= "table" or rawget(mt, "__tostring") ~= nil) then
    return safe_tostring(v)
  end
  if path[v] then return "<cycle>" end
  if depth >= opts.depth then return "{...}" end
  -- the array part, then the other keys, sorted
  local n = rawlen(v)
  local keys, more = {}, false
  for k in next, v do
    if not (math_type(k) == "integer" and k >= 1 and k <= n) then
      if #keys >= kMaxKeys then more = true break end
      keys[#keys + 1] = k
    end
  end
  local count = n + #keys
  local order = { number = 1, string = 2, boolean = 3 }
  sort(keys, function(a, b)
    local ta, tb = order[type(a)] or 4, order[type(b)] or 4
    if ta ~= tb then return ta < tb end
    if ta <= 2 then return a < b end
    return safe_tostring(a) < safe_tostring(b)
  end)
  path[v] = true
  local parts, multiline = {}, false
  local function add(key, value)
    if #parts >= opts.items or budget.left <= 0 then return false end
    budget.left = budget.left - 1
    local s = render(value, opts, depth + 1, path, budget, indent .. "  ")
    if s:find("\n", 1, true) then multiline = true end
    parts[#parts + 1] = key and (key .. " = " .. s) or s
    return true
  end
  local shown = 0
  for i = 1, n do
    local value = rawget(v, i)
    if not add(nil, value) then break end
    shown = shown + 1
  end
  for _, k in ipairs(keys) do
    local key
    if is_name(k) then
      key = k
    else
      key = "[" .. render(k, opts, opts.depth, path, budget, indent) .. "]"
    end
    if not add(key, rawget(v, k)) then break end
    shown = shown + 1
  end
  path[v] = nil
  if shown < count or more then
    parts[#parts + 1] = more and "... (more)" or format("... (%d more)", count - shown)
  end
  if #parts == 0 then return "{}" end
  local flat = "{ " .. concat(parts, ", ") .. " }"
  if not multiline and #flat + #indent <= opts.width then return flat end
  local inner = indent .. "  "
  return "{\n" .. inner .. concat(parts, ",\n" .. inner) .. "\n" .. indent .. "}"
end

function gaitlab.pretty(value, options)
  local opts = {}
  for k, d in pairs(defaults) do
    local given = type(options) == "table" and rawget(options, k) or nil
    if given ~= nil and (math_type(given) ~= "integer" or given < 0) then
      error(format("bad argument #2 to 'pretty' (field '%s': a whole number >= 0 expected)", k), 2)
    end
    opts[k] = given or d
  end
  if options ~= nil and type(options) ~= "table" then
    error("bad argument #2 to 'pretty' (table expected, got " .. type(options) .. ")", 2)
  end
  return render(value, opts, 0, {}, { left = opts.total }, "")
end
