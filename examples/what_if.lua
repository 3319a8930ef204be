-- What if: a pitch-yaw snake crawls for 4 s; then three copies of the simulation, made at that
-- moment, each bend the yaw joints a different way for 6 s more, while the original goes on
-- straight. A copy starts from exactly the original's state (bodies, contacts, controllers)
-- and steps bit for bit as the original would: only the change makes a difference.
-- Then the same world is built into two fresh simulations that run side by side.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
robot:group("yaw"):drive(gaitlab.controllers.offset{ angle = 0 })
local sim = gaitlab.simulation{ world = world }
sim:run(4)

local copies = {}
for _, angle in ipairs({ -20, 10, 20 }) do
  local copy = sim:clone()
  copy:robot("snake"):controllers()[2].angle = angle   -- the copy's offset only
  copies[#copies + 1] = { angle = angle, sim = copy }
end
sim:run(6)
print(string.format("straight on:        turned %+6.1f deg", sim:robot("snake"):turned()))
for _, c in ipairs(copies) do
  c.sim:run(6)
  print(string.format("yaw joints %+3d deg: turned %+6.1f deg", c.angle,
                      c.sim:robot("snake"):turned()))
end

-- one world, several simulations: each new one drives fresh copies of the world's
-- controllers, with the parameters they have when it is built
local results = {}
for _, amplitude in ipairs({ 20, 40 }) do
  robot:controllers()[1].amplitude = amplitude
  local s = gaitlab.simulation{ world = world, record = false }
  s:run(5)
  results[#results + 1] = string.format("amplitude %d deg: %.3f m", amplitude,
                                        s:robot("snake"):displacement():norm())
end
print("in 5 s from the start, " .. table.concat(results, ", "))
