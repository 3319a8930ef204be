-- two simulations: each records into its own run folder
for _, n in ipairs{ 2, 3 } do
  local robot = gaitlab.robot.chain{ name = "worm" .. n, modules = n }
  local world = gaitlab.world()
  world:add(robot)
  gaitlab.simulation{ world = world }:run(0.1)
end
