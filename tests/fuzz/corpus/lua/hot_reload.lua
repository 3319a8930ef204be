-- a controller file rewritten while it runs: good versions replace it, bad ones are refused
local function write(code)
  local f = assert(io.open("wave.lua", "w"))
  f:write(code)
  f:close()
end
write([[
return gaitlab.controller{
  name = "wave",
  params = { amplitude = { 30, min = 0, max = 60 } },
  values = { "time" },
  snapshot = function(self) return { n = self.n } end,
  step = function(self, dt)
    self.n = (self.n or 0) + 1
    for m = 1, self.joints do self.time[m] = self.time[m] + dt self:set_angle(m, self.amplitude) end
  end,
}
]])
local Wave = gaitlab.controller.load("wave.lua")
print(Wave == gaitlab.controller.load("wave.lua"), Wave.file, Wave.version)
local robot = gaitlab.robot.chain{ modules = 3 }
local world = gaitlab.world{}
world:add(robot)
local ctl = robot:group("all"):drive(Wave{ amplitude = 50 })
local sim = gaitlab.simulation{ world = world }
sim:step(60)
write([[
return gaitlab.controller{
  name = "wave",
  params = { amplitude = { 10, min = 0, max = 20 }, speed = { 1, min = 0, max = 2 } },
  values = { "time", "extra" },
  on_reload = function(self, snap) self.n = snap and snap.n or -1 end,
  step = function(self, dt) self:set_angle(1, self.amplitude * self.speed) end,
}
]])
print(gaitlab.controller.reload())
print(Wave.version, ctl.amplitude, pcall(function() return ctl.speed end))
sim:step(60)
print(ctl.amplitude, ctl.speed, ctl:values().extra)
write("return gaitlab.controller{ name = 'wave', step = ")
print(gaitlab.controller.reload())
print(Wave.version, Wave.reload_error)
os.remove("wave.lua")
print(gaitlab.controller.reload())
sim:step(60)
