-- A snake driven by a built-in controller and a Lua controller with feedback, printed to the
-- last bit (%a): the module and gaitlab run must give the same run.
local robot = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-yaw" }
robot:sensor{ kind = "imu", module = 1 }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:box{ size = { 0.1, 0.1, 0.05 }, position = { 0.3, 0.1, 0.025 }, mass = 0.2 }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = -120 })
robot:group("yaw"):drive(gaitlab.controller{ name = "steer", values = { "target" },
  step = function(self, dt)
    local roll = self:sensor("imu1", "roll") or 0
    for m = 1, self.joints do
      self.target[m] = 10 * math.sin(m + self:joint_angle(m) / 30) - roll / 10
      self:set_angle(m, self.target[m])
    end
  end }())
local sim = gaitlab.simulation{ world = world, dt = 0.001, control_every = 20 }
sim:run(3)
local d = robot:displacement()
print(string.format("moved %a %a %a", d.x, d.y, d.z))
for _, b in ipairs(robot:bodies()) do
  print(string.format("%s %a %a %a", b.name, b.position.x, b.position.y, b.position.z))
end
for _, j in ipairs(robot:joints()) do print(string.format("%s %a", j.name, j.angle)) end
