-- Many snakes at once, for the viewer's frame rate (bench/viewer_fps.mjs):
--   gaitlab run bench/lua/crowd.lua --view -- ROBOTS [MODULES] [SECONDS]
-- ROBOTS 8-module pitch-pitch snakes side by side, each with its own sine, run at real time.
local robots = tonumber(arg[1] or "40")
local modules = tonumber(arg[2] or "8")
local seconds = tonumber(arg[3] or "60")

local world = gaitlab.world{ floor = { friction = 0.8 } }
local row = math.ceil(math.sqrt(robots))
for i = 0, robots - 1 do
  local robot = gaitlab.robot.chain{ name = "snake" .. i, modules = modules,
                                     connection = "pitch-pitch" }
  world:add(robot, { x = (i % row) * 1.0, y = math.floor(i / row) * 0.5 })
  robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5,
                                                       phase = 120 })
end
local sim = gaitlab.simulation{ world = world, record = false }
sim:run(seconds)
