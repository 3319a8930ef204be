-- Feedback from sensors: a caterpillar between two walls turns back before touching either.
-- Its controller (controllers/shuttle.lua) reads a range sensor on the tail and one on the head.
-- The rays point 45 degrees up, so the body's own rocking never points them at the floor.
local Shuttle = gaitlab.controller.load("controllers/shuttle.lua")

local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)                                   -- tail at x = 0, head at x = 0.576 m
world:box{ size = {0.05, 1, 0.3}, position = {-0.2, 0, 0.15} }    -- face at x = -0.175
world:box{ size = {0.05, 1, 0.3}, position = {0.776, 0, 0.15} }   -- face at x = 0.751
robot:sensor{ kind = "range", name = "back", module = 1, half = "tail", direction = {-1, 0, 1} }
robot:sensor{ kind = "range", name = "front", module = 8, half = "head", direction = {1, 0, 1} }
robot:group("pitch"):drive(Shuttle{ near = 0.1 })
local sim = gaitlab.simulation{ world = world }

-- gaps between the robot's ends (the 18 mm end halves around their centres) and the walls
local function gaps()
  local bodies = robot:bodies()
  return bodies[1].position.x - 0.018 + 0.175, 0.751 - (bodies[#bodies].position.x + 0.018)
end
local closest_back, closest_front = math.huge, math.huge
for _ = 1, 200 do                                  -- 20 s, sampled every 0.1 s
  sim:run(0.1)
  local back, front = gaps()
  closest_back, closest_front = math.min(closest_back, back), math.min(closest_front, front)
end
print(string.format("in %.0f s: closest to the back wall %.3f m, to the front wall %.3f m",
  sim.time, closest_back, closest_front))
assert(closest_back > 0.02 and closest_front > 0.02, "the robot touched a wall")

-- without feedback: the sensors switched off read nil, and the robot crawls into the wall
for _, s in ipairs(robot:sensors()) do s:off() end
sim:reset()
sim:run(8)
local back = gaps()
print(string.format("sensors off: after %.0f s the tail is %.3f m from the back wall", sim.time, back))
