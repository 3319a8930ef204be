-- a controller reading its joints and its robot's sensors, by name and by channel
local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
robot:sensor{ kind = "imu", name = "head", module = 4 }
robot:sensor{ kind = "contact", module = 1 }
local Feel = gaitlab.controller{
  name = "feel",
  values = { "seen" },
  step = function(self, dt)
    local imu = self:sensor("head")
    local touching = self:sensor("contact1", "contact")
    for m = 1, self.joints do
      self.seen[m] = self:joint_angle(m) + self:joint_velocity(m) * dt + self:joint_torque(m)
      self:set_angle(m, (imu and imu.pitch or 0) + (touching and 10 or -10))
    end
    print(pcall(self.sensor, self, "nope"))
    print(pcall(self.sensor, self, "head", "nope"))
    print(pcall(self.set_angle, self, self.joints + 1, 0))
  end,
}
local world = gaitlab.world{}
world:add(robot)
robot:group("all"):drive(Feel())
local sim = gaitlab.simulation{ world = world, control_every = 50 }
sim:step(200)
