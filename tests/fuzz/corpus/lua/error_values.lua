-- errors raised with values that are not strings, up to the end of the script
local Throw = gaitlab.controller{
  name = "throw",
  step = function(self)
    error(setmetatable({}, { __tostring = function() error("tostring fails too") end }))
  end,
}
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Throw())
local sim = gaitlab.simulation{ world = world }
print(pcall(sim.step, sim, 40))
print(ctl.error)
print(pcall(error))
print(pcall(error, nil))
print(select("#", pcall(error, {})))
error(setmetatable({}, { __tostring = function() return "the end" end }))
