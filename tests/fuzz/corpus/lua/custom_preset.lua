-- a world preset of one's own: parameters checked against their ranges and by check(p)
local Arena = gaitlab.world.preset{
  name = "arena",
  description = "a square of four walls",
  params = {
    size = { 1, min = 0.2, max = 5, unit = "m", doc = "side of the square" },
    walls = { 4, min = 0, max = 4, doc = "how many walls" },
  },
  check = function(p) if p.walls % 1 ~= 0 then return "walls must be a whole number" end end,
  build = function(p)
    local w = gaitlab.world{}
    for i = 1, p.walls do
      local a = (i - 1) * 90
      w:wall{ length = p.size, yaw = a, position = { math.cos(math.rad(a)) * p.size / 2, math.sin(math.rad(a)) * p.size / 2, 0 } }
    end
    return w, { x = -0.1 }
  end,
}
print(Arena, Arena.name)
local world, start = Arena{ size = 2 }
world:add(gaitlab.robot.chain{ modules = 2 }, start)
print(pcall(Arena, { walls = 2.5 }))
print(pcall(Arena, { size = 10 }))
print(pcall(Arena, { sise = 1 }))
print(pcall(gaitlab.world.preset, { name = "bad", build = 3 }))
