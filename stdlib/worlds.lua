-- World presets: gaitlab.world.preset{...} declares a world builder with named, range-checked
-- parameters; gaitlab.world.load(path) runs a world file (which returns a preset); and
-- gaitlab.worlds.<name> are the ready-made worlds of worlds/, embedded in the binary.
local gaitlab, registry = ...
local closest = registry["gaitlab.closest"]
local sources = registry["gaitlab.world_sources"]
-- the bounded reader: a directory, a FIFO, a device or a huge file is refused, never read
local read_source = registry["gaitlab.read_source"]
local getinfo, load = debug.getinfo, load
local G = _G

local Preset = { __name = "gaitlab.WorldPreset" }

-- the type name Lua's own messages would use (honours __name; gaitlab's types protect their
-- metatables, and getmetatable gives their name)
local function typename(v)
  local mt = getmetatable(v)
  if type(mt) == "string" then return mt end
  if type(mt) == "table" and type(mt.__name) == "string" then return mt.__name end
  return type(v)
end

-- raises "bad argument #1 to 'fn' (message)" at the caller of the function calling this (or
-- `depth` levels further up)
local function bad(fn, message, depth)
  error(string.format("bad argument #1 to '%s' (%s)", fn, message), 3 + (depth or 0))
end

local function sorted_keys(t)
  local names = {}
  for k in pairs(t) do names[#names + 1] = k end
  table.sort(names)
  return names
end

local function did_you_mean(word, names)
  local c = closest(word, names)
  return c and ("; did you mean '" .. c .. "'?") or ""
end

-- checks one parameter declaration { default, min =, max =, unit =, integer =, doc = }
local function check_param(name, p)
  if type(p) ~= "table" or type(p[1]) ~= "number" then
    bad("preset", string.format("params.%s: { default, min = , max = } expected", name), 1)
  end
  for k in pairs(p) do
    if k ~= 1 and k ~= "min" and k ~= "max" and k ~= "unit" and k ~= "integer" and k ~= "doc" then
      bad("preset", string.format("params.%s: unknown key '%s'%s", name, tostring(k),
        did_you_mean(tostring(k), { "min", "max", "unit", "integer", "doc" })), 1)
    end
  end
  if type(p.min) ~= "number" or type(p.max) ~= "number" or not (p.min <= p[1] and p[1] <= p.max) then
    bad("preset", string.format("params.%s: numbers min <= default <= max expected", name), 1)
  end
end

--- gaitlab.world.preset{ name =, description =, params = { name = { default, min =, max =,
--- unit =, integer =, doc = } }, check = function(p) return nil or message end,
--- build = function(p) return world [, start] end }
function gaitlab.world.preset(def)
  if type(def) ~= "table" then bad("preset", "table expected, got " .. typename(def)) end
  for k in pairs(def) do
    if k ~= "name" and k ~= "description" and k ~= "params" and k ~= "check" and k ~= "build" then
      bad("preset", "unknown key '" .. tostring(k) .. "'"
        .. did_you_mean(tostring(k), { "name", "description", "params", "check", "build" }))
    end
  end
  if type(def.name) ~= "string" or def.name == "" then
    bad("preset", "field 'name': string expected, got " .. typename(def.name))
  end
  if type(def.build) ~= "function" then
    bad("preset", "field 'build': function expected, got " .. typename(def.build))
  end
  if def.check ~= nil and type(def.check) ~= "function" then
    bad("preset", "field 'check': function expected, got " .. typename(def.check))
  end
  local params = def.params or {}
  if type(params) ~= "table" then bad("preset", "field 'params': table expected") end
  for name, p in pairs(params) do check_param(name, p) end
  return setmetatable({
    name = def.name,
    description = def.description or "",
    params = params,
    check = def.check,
    build = def.build,
  }, Preset)
end

-- preset{ params }: checks the parameters, fills in defaults, builds the world; returns the
-- world and, if the preset gives one, a placement for world:add(robot, start)
function Preset.__call(self, args)
  local fn = self.name
  if args == nil then args = {} end
  if type(args) ~= "table" then bad(fn, "table expected, got " .. typename(args)) end
  local names = sorted_keys(self.params)
  local p = {}
  for k, v in pairs(args) do
    if type(k) ~= "string" then bad(fn, "unexpected " .. type(k) .. " key (fields are named)") end
    local spec = self.params[k]
    if not spec then
      bad(fn, string.format("unknown key '%s'%s (parameters of '%s': %s)", k,
        did_you_mean(k, names), fn, table.concat(names, ", ")))
    end
    if type(v) ~= "number" then
      bad(fn, string.format("field '%s': number expected, got %s", k, typename(v)))
    end
    if spec.integer and math.type(v) ~= "integer" and v ~= math.floor(v) then
      bad(fn, string.format("field '%s': integer expected, got a fractional number", k))
    end
    if not (v >= spec.min and v <= spec.max) then
      bad(fn, string.format("%s must be in [%s, %s]%s (got %s)", k, spec.min, spec.max,
        spec.unit and spec.unit ~= "" and (" " .. spec.unit) or "", v ~= v and "nan" or v))
    end
    p[k] = spec.integer and math.tointeger(v) or v
  end
  for _, name in ipairs(names) do
    if p[name] == nil then p[name] = self.params[name][1] end
  end
  -- what one parameter's range cannot say (e.g. min_size <= max_size)
  local problem = self.check and self.check(p)
  if problem then bad(fn, problem) end
  local world, start = self.build(p)
  if typename(world) ~= "gaitlab.World" then
    error(string.format("world preset '%s': build must return a gaitlab.World, got %s", fn,
      typename(world)), 2)
  end
  return world, start
end

Preset.__tostring = function(self) return "gaitlab.WorldPreset '" .. self.name .. "'" end

-- world files see the globals, with gaitlab bound even where it is not a global (require)
local env = setmetatable({ gaitlab = gaitlab }, { __index = G })

-- the folder of the innermost Lua file on the stack above `level` ("" if none)
local function caller_dir(level)
  while true do
    local info = getinfo(level + 1, "S")
    if not info then return "" end
    if info.source:sub(1, 1) == "@" then
      return info.source:sub(2):match("^(.*)/[^/]*$") or ""
    end
    level = level + 1
  end
end

-- environment files (XML) are read by the C function this replaces
local load_environment = gaitlab.world.load

--- gaitlab.world.load(path): runs a world file (relative paths are relative to the calling
--- script's folder) and returns the preset it returns; FILE.xml is an environment file, read
--- into a world (or nil and a message)
function gaitlab.world.load(path)
  if type(path) ~= "string" then bad("load", "string expected, got " .. typename(path)) end
  -- the system would stop at the zero and read another file (p.xml\0x: an XML file as Lua)
  if path:find("\0", 1, true) then
    error(string.format("a path cannot contain a zero byte (got '%s\\x00...')",
      path:match("^[^\0]*")), 2)
  end
  if path:match("%.xml$") then return load_environment(path) end
  local resolved = path
  if path:sub(1, 1) ~= "/" then
    local dir = caller_dir(2)
    if dir ~= "" then resolved = dir .. "/" .. path end
  end
  local text, why = read_source(resolved)
  if not text then error(string.format("cannot load world '%s': %s", path, why), 2) end
  local chunk, message = load(text, "@" .. resolved, "t", env)
  if not chunk then error(message, 2) end
  local preset = chunk()
  if getmetatable(preset) ~= Preset then
    error(string.format("%s: a world file must return gaitlab.world.preset{...}, got %s",
      resolved, typename(preset)), 2)
  end
  return preset
end

-- the ready-made worlds, by name
gaitlab.worlds = {}
for _, name in ipairs(sorted_keys(sources)) do
  local chunk = assert(load(sources[name], "=worlds/" .. name .. ".lua", "t", env))
  local preset = chunk()
  assert(getmetatable(preset) == Preset, "worlds/" .. name .. ".lua must return a preset")
  gaitlab.worlds[name] = preset
end
