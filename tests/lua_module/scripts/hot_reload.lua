-- A controller file changed while the script runs: a version that does not parse is refused
-- (the class keeps its last good version), a version that fails at run time fails the run.
local file = "wave_controller.lua"  -- next to the script: a copy the tests make
local function write(text)
  local f = assert(io.open(file, "w"))
  f:write(text)
  f:close()
end
write([[return gaitlab.controller{ name = "wave", params = { gain = { 10, min = 0, max = 90 } },
  step = function(self) self:set_angle(1, self.gain) end }]])
local Wave = gaitlab.controller.load(file)
local robot = gaitlab.robot.chain{ name = "snake", modules = 2 }
local world = gaitlab.world()
world:add(robot)
local wave = Wave{}
robot:group{ 1 }:drive(wave)
local sim = gaitlab.simulation{ world = world }
sim:run(0.1)
write("return gaitlab.controller{ name = 'wave', step = function(self) end")
local ok, err = gaitlab.controller.reload()
print("syntax error:", ok, err)
print("version", Wave.version, Wave.reload_error)
write("while true do end")
ok, err = gaitlab.controller.reload()
print("endless:", ok, err)
write([[return gaitlab.controller{ name = "wave", params = { gain = { 10, min = 0, max = 90 } },
  step = function(self) self:set_angle(1, self.gian) end }]])
print("runtime error reloads:", gaitlab.controller.reload(), Wave.version)
local ran, failure = pcall(sim.run, sim, 0.1)
print("run:", ran, failure)
os.remove(file)
error("done: " .. tostring(wave.failed))
