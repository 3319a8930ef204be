-- Whether a standard gait's chain passes through itself (docs/performance.md, section 12, "The
-- long rolling chains pass through themselves"): runs GAIT on N modules on a floor of friction MU
-- from the straight start for SECONDS at the defaults, the chain's bodies not colliding with
-- each other (self_collision off), and prints the engine's warning if it passes through itself.
--
--   gaitlab run bench/lua/self_pass.lua --no-record GAIT N MU SECONDS [START]
--   --> "py-roll 32 0.3, start 0: passes through itself at t = 0.88 s"
--       "py-roll-arc 32 0.3, start 0: keeps its bodies apart for 40 s"
-- GAIT: pp, py-roll, py-wave or py-roll-arc (bench/lua/standard_gaits.lua).
local gaits = require "standard_gaits"

local gait, n, mu, seconds, start = arg[1], tonumber(arg[2]), tonumber(arg[3]), tonumber(arg[4]),
                                    tonumber(arg[5] or "0")
if not (gait and n and mu and seconds and start) then
  error("usage: self_pass.lua GAIT N MU SECONDS [START]", 0)
end
local robot = gaitlab.robot.chain{ name = "snake", modules = n, connection = gaits.connection(gait) }
local world = gaitlab.world{ floor = { friction = mu } }
world:add(robot)
gaits.drive(robot, gait, { frequency = 0.5, start = start })
local sim = gaitlab.simulation{ world = world, control_every = 10, record = false }
sim:run(seconds)
local at
for _, w in ipairs(sim.warnings) do
  at = at or w:match("passes through itself at t = ([%d.]+ s)")
end
print(string.format("%s %d %g, start %g: %s", gait, n, mu, start,
                    at and ("passes through itself at t = " .. at)
                      or string.format("keeps its bodies apart for %g s", seconds)))
