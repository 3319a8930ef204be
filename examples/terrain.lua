-- Terrain from a height map. A heightfield reads a grey-level PNG (white = max_height, black =
-- 0; the image's top row is the terrain's +y edge) stretched over length x width metres; the
-- path is relative to this script. examples/terrain.png is 96 x 64 pixels, made by
-- tools/make_terrain_png.lua. A heightfield can also come from a Lua function:
--   world:heightfield{ length = 2, width = 1, heights = function(x, y) return 0.02 * x end }
-- (x, y measured from the terrain's centre), as gaitlab.worlds.hills does.
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:heightfield{ image = "terrain.png", max_height = 0.04, length = 1.5, width = 1.0,
                   position = { 0.6, 0, 0 } }

-- the snake starts across the terrain's left part, dropped from just above its highest point
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
world:add(robot, { x = -0.1, y = -0.1, z = 0.045 })
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = -120 })
local sim = gaitlab.simulation{ world = world }

for t = 5, 20, 5 do
  sim:run(5)
  local p = robot:position()
  print(string.format("t = %2d s: x %.3f, y %+.3f, z %.3f m", t, p.x, p.y, p.z))
end
