-- The standard gaits of bench/lua/convergence.lua and bench/lua/servo_load.lua (docs/performance.md,
-- section 12): pp, the travelling wave of a pitch-pitch chain (Cube Revolutions), 40 deg and 120
-- deg between neighbours (`direction` -1 reverses the wave); py-roll, the rolling gait of a
-- pitch-yaw chain (Gonzalez-Gomez et al., CLAWAR 2006: all joints of a plane in phase, the yaw
-- joints 90 deg behind); py-wave, the benchmark's pitch-yaw gait (docs/performance.md,
-- "Workload": a 40 deg pitch wave and a 20 deg yaw wave, 120 deg between neighbours).
-- py-roll-arc: the rolling gait with the 8-module robot's arc at any length, 40 deg x 8 / N per
-- joint from 8 modules up (py-roll itself up to 8). It is the grid's rolling gait (`names`,
-- since 2026-12-01): py-roll's arc turns about 20 deg per module, 640 deg at 32, which a chain
-- cannot make without passing through itself (docs/performance.md, "The long rolling chains
-- pass through themselves"). py-roll stays in `known`, for the tables measured with it.
--
--   local gaits = require "standard_gaits"
--   gaits.drive(robot, "py-roll-arc", { frequency = 0.5, direction = 1, start = 72 })
--   gaits.connection("py-roll-arc")  --> "pitch-yaw"
-- `start` (deg) is added to every joint's phase.
local gaits = { names = { "pp", "py-roll-arc", "py-wave" },
                known = { "pp", "py-roll", "py-wave", "py-roll-arc" } }

-- true if `gait` is one of the gaits above
function gaits.is_known(gait)
  for _, g in ipairs(gaits.known) do
    if g == gait then return true end
  end
  return false
end

-- the known gaits for a message: "pp, py-roll, py-wave or py-roll-arc"
function gaits.listed()
  local k = gaits.known
  return table.concat(k, ", ", 1, #k - 1) .. " or " .. k[#k]
end

function gaits.connection(gait)
  return gait == "pp" and "pitch-pitch" or "pitch-yaw"
end

function gaits.drive(robot, gait, o)
  local sine = gaitlab.controllers.sine
  local function wrap(a) return (a + 180) % 360 - 180 end
  local f, s, direction = o.frequency or 0.5, wrap(o.start or 0), o.direction or 1
  if gait == "pp" then
    robot:group("pitch"):drive(sine{ amplitude = 40, frequency = f, phase = 120 * direction,
                                     phase0 = s })
  elseif gait == "py-roll" or gait == "py-roll-arc" then
    local a = 40
    if gait == "py-roll-arc" then a = 40 * math.min(1, 8 / #robot:joints()) end
    robot:group("pitch"):drive(sine{ amplitude = a, frequency = f, phase = 0, phase0 = s })
    robot:group("yaw"):drive(sine{ amplitude = a, frequency = f, phase = 0,
                                   phase0 = wrap(-90 + s) })
  elseif gait == "py-wave" then
    robot:group("pitch"):drive(sine{ amplitude = 40, frequency = f, phase = 120, phase0 = s })
    robot:group("yaw"):drive(sine{ amplitude = 20, frequency = f, phase = 120, phase0 = s })
  else
    error("unknown gait '" .. tostring(gait) .. "' (expected " .. gaits.listed() .. ")", 0)
  end
end

return gaits
