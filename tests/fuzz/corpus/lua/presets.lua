-- every ready-made world with its parameters, and a robot at its start placement
for name, preset in pairs(gaitlab.worlds) do
  print(name, preset.name, preset.description)
  for p, spec in pairs(preset.params) do print(" ", p, spec[1], spec.min, spec.max, spec.unit, spec.doc) end
end
local worlds = {
  gaitlab.worlds.flat{ friction = 0.3 },
  gaitlab.worlds.slippery(),
  gaitlab.worlds.sticky{},
  gaitlab.worlds.ramp{ slope = 20, length = 0.5, width = 0.3, top = 0.2, friction = 0.9 },
  gaitlab.worlds.stairs{ steps = 2, step_height = 0.01, step_depth = 0.1, distance = 0.5 },
  gaitlab.worlds.pipe{ radius = 0.06, sides = 6, length = 0.5, entrance = 0.1 },
  gaitlab.worlds.rubble{ count = 5, length = 0.3, width = 0.3, seed = 2 },
  gaitlab.worlds.hills{ height = 0.02, wavelength = 0.5, length = 1, width = 1 },
}
print(pcall(gaitlab.worlds.ramp, { slope = 90 }))
print(pcall(gaitlab.worlds.stairs, { steps = 1.5 }))
print(pcall(gaitlab.worlds.rubble, { cont = 3 }))
for name, preset in pairs(gaitlab.worlds) do
  local world, start = preset()
  local robot = gaitlab.robot.chain{ name = name, modules = 2 }
  world:add(robot, start)
  gaitlab.simulation{ world = world }:step(5)
end
print(#worlds)
