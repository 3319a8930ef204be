-- A long chain of boxes (8 x 5 x 3 cm, 50 g) joined by pitch hinges, lying on the floor, still
-- or driven by the standard pitch-pitch wave; with BRANCH=1 a side link on link SIDE (links are
-- numbered from 0 at the tail; default: the tenth from the head, LINKS - 10), a body of three
-- hinges: the block's profile instead of its band. Prints whether it stayed finite, how far its
-- centre of mass moved and the CPU time per step (docs/performance.md, "Long chains").
--
--   LINKS=2000 SECONDS=0.2 [BRANCH=1 [SIDE=K]] [DRIVE=1] gaitlab run bench/lua/long_chain.lua
local function setting(name, default, ok, expected)
  local text = os.getenv(name) or default
  local v = tonumber(text)
  if not (v and ok(v)) then
    error(string.format("%s: %s expected, got '%s'", name, expected, text), 0)
  end
  return v
end
local branch = os.getenv("BRANCH") == "1"
local drive = os.getenv("DRIVE") == "1"
local most = branch and 9999 or 10000  -- a robot's bodies, with the side link's
local links = setting("LINKS", "2000", function(v) return v % 1 == 0 and v >= 12 and v <= most end,
                      string.format("a whole number of links in [12, %d]", most))
local seconds = setting("SECONDS", "0.2", function(v) return v > 0 and v <= 1e6 end,
                        "seconds in (0, 1e6]")
local side = setting("SIDE", tostring(links - 10),
                     function(v) return v % 1 == 0 and v >= 0 and v <= links - 1 end,
                     string.format("a link number in [0, %d]", links - 1))

local bodies, joints = {}, {}
for i = 0, links - 1 do
  bodies[#bodies + 1] = { name = "l" .. i, size = { 0.08, 0.05, 0.03 }, mass = 0.05,
                          position = { 0.08 * i + 0.04, 0, 0.015 } }
end
for i = 1, links - 1 do
  joints[#joints + 1] = { name = "j" .. i, parent = "l" .. (i - 1), child = "l" .. i,
                          pivot = { 0.08 * i, 0, 0.015 }, axis = { 0, 1, 0 }, min = -60, max = 60 }
end
if branch then
  local m = side
  bodies[#bodies + 1] = { name = "side", size = { 0.05, 0.08, 0.03 }, mass = 0.05,
                          position = { 0.08 * m + 0.04, 0.065, 0.015 } }
  joints[#joints + 1] = { name = "side", parent = "l" .. m, child = "side",
                          pivot = { 0.08 * m + 0.04, 0.025, 0.015 }, axis = { 1, 0, 0 },
                          min = -60, max = 60 }
end
local robot = gaitlab.robot.new{ name = "chain", bodies = bodies, joints = joints }
local world = gaitlab.world()
world:add(robot)
if drive then
  robot:group("all"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
end
local sim = gaitlab.simulation{ world = world, record = false }
local r = sim:robot("chain")
local p0 = r:position()
local t0 = os.clock()
local ok, err = pcall(sim.run, sim, seconds)
local cpu = os.clock() - t0
local d = r:position() - p0
local what = string.format("links %d%s%s", links,
                           branch and string.format(" + side link on link %d", side) or "",
                           drive and " driven" or " still")
if ok then
  print(string.format("%s: finite, moved %.3g mm, %.1f ms per step", what, 1000 * d:norm(),
                      1000 * cpu / (seconds / sim.dt)))
else
  print(what .. ": failed: " .. tostring(err))
end
