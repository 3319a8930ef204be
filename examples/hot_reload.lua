-- Hot reload. In real use you edit a controller file in your editor while
-- a long run goes on, and gaitlab picks the change up at the next control tick; here the script
-- rewrites the file itself and calls gaitlab.controller.reload() so it runs the same every time.
local path = os.tmpname()

local function write(code)
  local f = assert(io.open(path, "w"))
  f:write(code)
  f:close()
end

-- version 1: a travelling wave
write([[
return gaitlab.controller{
  name = "wave",
  params = { amplitude = { 30, min = 0, max = 60, unit = "deg" } },
  values = { "time" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self:set_angle(m, self.amplitude * math.sin(math.pi * self.time[m] + (m - 1) * 2.1))
    end
  end,
}
]])
local Wave = gaitlab.controller.load(path)

local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
local ctl = robot:group("pitch"):drive(Wave{ amplitude = 40 })
local sim = gaitlab.simulation{ world = world }
sim:run(5)
print(string.format("v1: moved %.3f m", robot:displacement():norm()))

-- version 2: the wave runs the other way; 'amplitude' (40) and the clocks in 'time' carry over
write([[
return gaitlab.controller{
  name = "wave",
  params = { amplitude = { 30, min = 0, max = 60, unit = "deg" } },
  values = { "time" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self:set_angle(m, self.amplitude * math.sin(math.pi * self.time[m] - (m - 1) * 2.1))
    end
  end,
}
]])
assert(gaitlab.controller.reload())
sim:run(5)
print(string.format("v2: amplitude %g, clock %.2f s", ctl.amplitude, ctl:values().time[1]))

-- a version with an error would be reported ("gaitlab: reload failed: FILE:LINE: ...") and
-- version 2 would keep running: see docs/lua-controllers.md
print(string.format("moved %.3f m in %.0f s, %d reload(s)", robot:displacement():norm(), sim.time,
  Wave.version))
os.remove(path)
