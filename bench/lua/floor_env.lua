-- The floor a benchmark runs on, from its environment variables, shared by the bench scripts
-- (docs/performance.md). PREFIX_RIGID=1 makes it rigid; PREFIX_STIFFNESS (N/m) and
-- PREFIX_DAMPING (N s/m) set a compliant one's values, each alone or both (the other keeps the
-- engine's default); none of them: the engine's default floor (compliant, 3e3 N/m and 60 N s/m
-- per contact point). gaitlab.world checks the values (a rigid floor with a stiffness is its
-- error, named); this names a variable that is not a number.
--
--   local floor_env = require "floor_env"
--   local floor = floor_env("STEADY", "steady_speed.lua")  -- read once, before any run
--   gaitlab.world{ floor = floor_env.on(floor, friction) }  -- the floor's keys with a friction
--   floor_env.describe(floor)                              -- "the default floor", ...
local function number(script, name)
  local text = os.getenv(name)
  if text == nil then return nil end
  local v = tonumber(text)
  if not v then error(string.format("%s: %s: a number expected, got '%s'", script, name, text), 0) end
  return v
end

local M = {}

function M.describe(floor)
  if floor.rigid then return "a rigid floor" end
  if not floor.stiffness and not floor.damping then return "the default floor" end
  local function value(v, unit) return v and string.format("%g %s", v, unit) or "the default" end
  return string.format("a floor of stiffness %s, damping %s", value(floor.stiffness, "N/m"),
                       value(floor.damping, "N s/m"))
end

-- a copy of the floor's keys with a friction, for gaitlab.world{ floor = }
function M.on(floor, friction)
  return { friction = friction, rigid = floor.rigid, stiffness = floor.stiffness, damping = floor.damping }
end

return setmetatable(M, { __call = function(_, prefix, script)
  local rigid = os.getenv(prefix .. "_RIGID")
  if rigid ~= nil and rigid ~= "0" and rigid ~= "1" then
    error(string.format("%s: %s_RIGID: 1 (a rigid floor) or 0 expected, got '%s'", script, prefix, rigid), 0)
  end
  return { rigid = rigid == "1" or nil, stiffness = number(script, prefix .. "_STIFFNESS"),
           damping = number(script, prefix .. "_DAMPING") }
end })
