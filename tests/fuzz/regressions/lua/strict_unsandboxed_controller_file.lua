-- strict: a controller file loaded without its sandbox may write files in the run folder, but
-- runs no command (the harness once created its own marker file this way and reported it)
local f = assert(io.open("c.lua", "w"))
f:write([[
pcall(os.execute, "touch gaitlab_injected")
pcall(io.popen, "touch gaitlab_injected")
local g = io.open("written_by_controller", "w")
if g then g:write("x") g:close() end
return gaitlab.controller{ name = "c", step = function(self) end }
]])
f:close()
print(gaitlab.controller.load("c.lua", { sandbox = false }))
print(pcall(gaitlab.controller.load, "c.lua"))
print(io.open("written_by_controller") ~= nil)
