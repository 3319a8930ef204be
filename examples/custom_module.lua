-- Custom module types. gaitlab.modules holds the module library (y1, the default, and cube);
-- gaitlab.module{...} adds a type of your own (see docs/modules.md). Sizes in m, mass in kg,
-- angles in degrees, max_speed in deg/s, max_torque in N·m.
local tube = gaitlab.module{
  name = "tube",
  shape = "cylinder",   -- a cylinder along the chain: rolls easily
  length = 0.1, radius = 0.03, mass = 0.08,
  range = { -60, 60 },  -- joint range, degrees
  max_speed = 180,      -- deg/s
  max_torque = 1.0,     -- N·m
}
print(string.format("%s: %s, %.0f mm long, %.0f g, +-%.0f deg", tube.name, tube.shape,
  tube.length * 1000, tube.mass * 1000, tube.range[2]))

-- the same gait on three robots: y1 modules, cube modules, tube modules
for _, module in ipairs{ "y1", "cube", tube } do
  local robot = gaitlab.robot.chain{ modules = 6, connection = "pitch-yaw", module = module }
  local world = gaitlab.worlds.flat()
  world:add(robot)
  robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30, frequency = 0.5,
                                                       phase = -120 })
  local sim = gaitlab.simulation{ world = world }
  sim:run(10)
  local mass = 0
  for _, body in ipairs(robot:bodies()) do mass = mass + body.mass end
  local d = robot:displacement()
  print(string.format("%-5s %d joints, %.2f kg: moved %.3f m (x %.3f, y %.3f)",
    type(module) == "string" and module or module.name, #robot, mass, d:norm(), d.x, d.y))
end
