-- every kind of world object, chained, with its triangles and its string form
local world = gaitlab.world{ floor = { friction = 0.5 } }
world:box{ size = { 0.1, 0.2, 0.05 }, position = { 0.5, 0, 0.025 }, yaw = 30, mass = 0.1, friction = 0.4 }
  :wall{ length = 1, height = 0.1, thickness = 0.02, position = { 0, 0.4, 0 }, yaw = 0 }
  :ramp{ slope = 15, length = 0.4, width = 0.3, position = { 1, 0, 0 } }
  :stairs{ steps = 3, step_height = 0.01, step_depth = 0.1, width = 0.3, landing = 0.1, position = { 1.5, 0, 0 } }
  :cylinder{ radius = 0.02, length = 0.3, lying = true, yaw = 90, position = { 0.3, 0, 0.02 }, mass = 0.05 }
  :pipe{ radius = 0.06, thickness = 0.005, length = 0.5, sides = 8, position = { -1, 0, 0 } }
  :rubble{ length = 0.3, width = 0.3, count = 10, min_size = 0.01, max_size = 0.02, min_height = 0.002,
           max_height = 0.005, seed = 7, position = { 2, 0, 0 } }
  :heightfield{ length = 0.5, width = 0.5, heights = function(x, y) return 0.01 * (x + y) end,
                samples = { 8, 6 }, position = { -2, 0, 0 } }
  :heightfield{ length = 0.5, width = 0.5, heights = { { 0, 0.01, 0 }, { 0.02, 0, 0.01 } }, position = { -3, 0, 0 } }
  :heightfield{ image = "terrain.png", max_height = 0.02, length = 0.5, width = 0.4, position = { -4, 0, 0 } }
local robot = gaitlab.robot.chain{ modules = 3 }
world:add(robot, { x = 0.2, y = -0.2, z = 0.01, yaw = 45, pitch = 5, roll = 10 })
print(world)
local tris = world:triangles()
print(#tris, tris[1] and tris[1].kind, tris[1] and #tris[1].vertices)
local sim = gaitlab.simulation{ world = world }
sim:step(20)
for _, o in ipairs(sim:objects()) do print(o.object, o.position.z, o.orientation.w, o.velocity.x) end
