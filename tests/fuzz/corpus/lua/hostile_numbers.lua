-- numbers no argument should take: NaN, infinities, integers beyond every range
local bad = { 0 / 0, 1 / 0, -1 / 0, 2^31, 2^32 + 30, 2^53, 2^63, -2^63, math.maxinteger,
              math.mininteger, 1e308, -1e-308, -0.0, "12", "x" }
for _, v in ipairs(bad) do
  print(pcall(gaitlab.robot.chain, { modules = v }))
  print(pcall(gaitlab.world, { floor = { friction = v }, gravity = { v, 0, 0 } }))
  print(pcall(gaitlab.controllers.sine, { amplitude = v, frequency = v }))
  local robot = gaitlab.robot.chain{ modules = 2 }
  local world = gaitlab.world{}
  print(pcall(world.add, world, robot, { x = v, yaw = v }))
  print(pcall(world.box, world, { size = { v, 1, 1 }, mass = v }))
  print(pcall(gaitlab.simulation, { world = world, dt = v }))
  print(pcall(gaitlab.simulation, { world = world, control_every = v, seed = v, solver_iterations = v }))
  local ok, sim = pcall(gaitlab.simulation, { world = world })
  if ok then
    print(pcall(sim.step, sim, v))
    print(pcall(sim.run, sim, v))
  end
  print(pcall(robot.group, robot, { v }))
end
