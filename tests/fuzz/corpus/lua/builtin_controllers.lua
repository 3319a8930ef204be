-- every built-in controller, its parameters and values, on groups of a yaw-yaw and a pitch-pitch robot
local a = gaitlab.robot.chain{ name = "a", modules = 5, connection = "yaw-yaw" }
local b = gaitlab.robot.chain{ name = "b", modules = 4, module = "cube" }
local world = gaitlab.world{}
world:add(a)
world:add(b, { y = 0.5, yaw = 90 })
local ctls = {}
for name, make in pairs(gaitlab.controllers) do
  local ok, c = pcall(make, {})
  if ok then
    ctls[#ctls + 1] = c
    local p = c:params()
    for k, v in pairs(p) do c[k] = v.max end
    print(name, c.name, tostring(c), c.failed, c.error)
  end
end
a:group("all"):drive(ctls[1])
a:group{ 1, 3, 5 }:drive(ctls[2])
b:group("pitch"):drive(ctls[3])
b:group{ 2 }:drive(ctls[4])
local sim = gaitlab.simulation{ world = world, seed = 3 }
sim:step(300)
for _, c in ipairs(ctls) do
  for k, v in pairs(c:values()) do print(k, #v) end
end
