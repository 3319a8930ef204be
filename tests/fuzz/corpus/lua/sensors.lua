-- one sensor of every kind: read, switched off and on, their channels and fields
local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
local world = gaitlab.world{}
world:add(robot)
world:box{ size = { 0.1, 1, 0.3 }, position = { 0.6, 0, 0.15 } }
local s = {
  robot:sensor{ kind = "joint", joint = 2 },
  robot:sensor{ kind = "imu", module = 4, half = "tail" },
  robot:sensor{ kind = "contact", module = 1, enabled = false },
  robot:sensor{ kind = "range", name = "ahead", module = 4, direction = { 1, 0, 0.2 }, max_range = 1 },
  robot:sensor{ kind = "position" },
}
print(gaitlab.sensor.kinds, #gaitlab.sensor.kinds, gaitlab.sensor.channels("imu")[1].name)
robot:group("pitch"):drive(gaitlab.controllers.sine{})
local sim = gaitlab.simulation{ world = world }
sim:step(50)
for _, x in ipairs(s) do
  local r = x:read()
  print(x, x.name, x.kind, x.joint, x.module, x.half, x.direction, x.max_range, x.enabled, r and next(r))
  for _, c in ipairs(x:channels()) do print(" ", c.name, c.unit) end
  x:off("console")
  print(x:read())
  x.enabled = true
  x:on("viewer")
end
print(robot:sensor("ahead"), #robot:sensors())
print(pcall(robot.sensor, robot, { kind = "imu", module = 9 }))
print(pcall(robot.sensor, robot, { kind = "joint", joint = 2, name = "joint2" }))
print(pcall(robot.sensor, robot, { kind = "laser" }))
print(pcall(robot.sensor, robot, { kind = "range", module = 1, max_range = 1000 }))
