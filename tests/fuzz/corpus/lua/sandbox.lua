-- controller files run in a sandbox: no files, processes, debug library or costly patterns
local f = assert(io.open("escape.lua", "w"))
f:write([[
local tried = {}
tried[#tried + 1] = pcall(function() return io.open("x", "w") end)
tried[#tried + 1] = pcall(function() return os.execute("true") end)
tried[#tried + 1] = pcall(function() return require("os") end)
tried[#tried + 1] = pcall(function() return debug.getregistry() end)
tried[#tried + 1] = pcall(function() return getmetatable("").__index end)
tried[#tried + 1] = pcall(function() return load("return 1") end)
tried[#tried + 1] = pcall(function() return setmetatable({}, { __gc = print }) end)
tried[#tried + 1] = pcall(function() return string.rep("a", 30):find("(a*)*b") end)
tried[#tried + 1] = pcall(function() return gaitlab.controller.write_template("blank", "../out.lua") end)
return gaitlab.controller{
  name = "escape",
  step = function(self, dt)
    local s = string.rep("a", 25)
    local ok = pcall(string.find, s, ".-.-.-.-.-.-.-.-b")
    self:set_angle(1, ok and 1 or 0)
  end,
}
]])
f:close()
local Escape = gaitlab.controller.load("escape.lua")
local Open = gaitlab.controller.load("escape.lua", { sandbox = false })
print(Escape, Open, pcall(gaitlab.controller.load, "escape.lua", { sandbox = 1 }))
print(pcall(gaitlab.controller.load, "nothing.lua"))
local robot = gaitlab.robot.chain{ modules = 2 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Escape())
local sim = gaitlab.simulation{ world = world, on_controller_error = "continue" }
sim:step(60)
print(ctl.failed, ctl.error)
