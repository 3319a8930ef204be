-- module types of one's own, based on others, and robots made of them
local tube = gaitlab.module{ name = "tube", shape = "cylinder", length = 0.1, radius = 0.03, mass = 0.08,
                             range = { -60, 60 }, max_speed = 180, max_torque = 1 }
local twist = gaitlab.module{ name = "twist", base = tube, axis = "twist", kp = 5, friction = 0.2 }
local flat = gaitlab.module{ name = "flat", base = "cube", width = 0.1, height = 0.02 }
for name, m in pairs(gaitlab.modules) do
  print(name, m.name, m.shape, m.length, m.width, m.height, m.radius, m.mass, m.axis,
        m.range[1], m.range[2], m.max_speed, m.max_torque, m.kp, m.friction, tostring(m))
end
print(pcall(gaitlab.module, { name = "y1" }))
print(pcall(gaitlab.module, { name = "bad", range = { 10, -10 } }))
print(pcall(gaitlab.module, { name = "bad", mass = -1 }))
print(pcall(function() tube.mass = 3 end))
local world = gaitlab.world{}
for i, m in ipairs{ tube, twist, "flat", "cube" } do
  local r = gaitlab.robot.chain{ modules = 3, module = m, connection = "pitch-yaw" }
  world:add(r, { y = i * 0.3 })
  r:group("all"):drive(gaitlab.controllers.sine{ amplitude = 20 })
  print(#r, pcall(r.group, r, "roll"), #r:bodies())
end
gaitlab.simulation{ world = world }:step(50)
