-- argument tables whose metamethods fail, loop, or hide the fields behind __index
local function failing() return setmetatable({}, { __index = function() error("index fails") end }) end
local hidden = setmetatable({}, { __index = { modules = 3, name = "hidden" } })
local len = setmetatable({ 1, 2 }, { __len = function() error("len fails") end })
local huge = setmetatable({ 1, 2 }, { __len = function() return 2^53 end })
print(pcall(gaitlab.robot.chain, failing()))
print(pcall(gaitlab.robot.chain, hidden))
print(pcall(gaitlab.world, failing()))
local robot = gaitlab.robot.chain{ modules = 3 }
print(pcall(robot.group, robot, len))
print(pcall(robot.group, robot, huge))
print(pcall(robot.group, robot, { 1, nil, 3 }))
local world = gaitlab.world{}
world:add(robot)
print(pcall(world.box, world, { size = failing() }))
print(pcall(world.heightfield, world, { heights = huge }))
print(pcall(gaitlab.simulation, { world = world, record = { series = len } }))
print(pcall(gaitlab.simulation, { world = world, record = { dir = "runs/x", series = huge } }))
print(pcall(gaitlab.controller, { name = "x", step = print, values = len }))
print(pcall(gaitlab.controller, { name = "x", step = print, params = { a = failing() } }))
print(pcall(gaitlab.module, setmetatable({}, { __index = function(t, k) return t[k] end })))
local deep = 1
for i = 1, 10000 do deep = { deep } end
print(pcall(gaitlab.robot.chain, { modules = deep }))
print(pcall(world.add, world, robot, deep))
