-- URDF interchange: import a robot written as URDF (examples/robots/inchworm.urdf: three box
-- links, two revolute joints), make it crawl, and export any gaitlab robot as URDF.
local worm = assert(gaitlab.robot.load_urdf("robots/inchworm.urdf"))
print(string.format("imported '%s': %d bodies, %d joints", worm.name, #worm:bodies(), #worm))
local world = gaitlab.world{ floor = { friction = 0.9 } }
world:add(worm)
worm:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 35, frequency = 0.8, phase = 90 })
local sim = gaitlab.simulation{ world = world }
sim:run(10)
local d = worm:displacement()
print(string.format("moved %.3f m (x %.3f, y %.3f)", d:norm(), d.x, d.y))

-- the other way: a gaitlab chain as URDF, for ROS tools (check_urdf, RViz, ...)
local path = os.tmpname()
local snake = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
assert(snake:save_urdf(path))
local copy = assert(gaitlab.robot.load_urdf(path))
print(string.format("exported and re-imported '%s': %d joints, joint 2 is a %s joint", copy.name,
  #copy, copy:joints()[2].role))
os.remove(path)
