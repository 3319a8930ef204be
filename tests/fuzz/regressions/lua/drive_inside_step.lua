-- group:drive from inside a controller's step: heap-use-after-free in Simulation::Phases::think
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local second = robot:group{ 2 }
local Spawner = gaitlab.controller{
  name = "spawner",
  step = function(self) second:drive(gaitlab.controllers.sine{}) end,
}
robot:group{ 1 }:drive(Spawner())
gaitlab.simulation{ world = world }:step(100)
