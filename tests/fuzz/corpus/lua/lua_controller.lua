-- a controller class written in Lua: parameters, per-joint values, instances with their own values
local Wave = gaitlab.controller{
  name = "wave",
  params = {
    amplitude = { 30, min = 0, max = 60, unit = "deg" },
    frequency = { 0.5, min = 0, max = 5, unit = "Hz" },
  },
  values = { "time", "angle" },
  step = function(self, dt)
    for m = 1, self.joints do
      self.time[m] = self.time[m] + dt
      self.angle[m] = self.amplitude * math.sin(2 * math.pi * self.frequency * self.time[m] + m)
      self:set_angle(m, self.angle[m])
    end
  end,
}
print(Wave.name, Wave.file, Wave.version, Wave.reload_error, Wave.instruction_budget, tostring(Wave))
local robot = gaitlab.robot.chain{ name = "worm", modules = 6 }
local world = gaitlab.world{}
world:add(robot)
local c1 = robot:group{ 1, 2, 3 }:drive(Wave{ amplitude = 40 })
local c2 = robot:group{ 4, 5, 6 }:drive(Wave())
local sim = gaitlab.simulation{ world = world }
sim:run(0.3)
c2.frequency = 2
sim:run(0.3)
print(c1:values().time[1], c2:values().angle[3], c1:params().amplitude.value)
