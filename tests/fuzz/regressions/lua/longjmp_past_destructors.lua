-- argument tables whose __index or __len raise: the bindings' C++ objects are never destroyed
local function failing() return setmetatable({}, { __index = function() error("no") end }) end
print(pcall(gaitlab.world, failing()))
print(pcall(gaitlab.controller, { name = "x", step = print, values = setmetatable({}, { __len = error }) }))
local world = gaitlab.world{}
print(pcall(gaitlab.simulation, { world = world, on_controller_error = "stop",
                                  record = { series = setmetatable({}, { __len = error }) } }))
