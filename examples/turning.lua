-- Turning: a pitch-yaw snake crawls with a sine on its pitch joints while an offset bends its
-- yaw joints; overlapping or separate groups, their targets add up. Change the offset's sign to
-- turn the other way, or set it to 0 to go straight.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-yaw" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local turn = robot:group("yaw"):drive(gaitlab.controllers.offset{ angle = 20 })
local sim = gaitlab.simulation{ world = world }

sim:run(10)
local d = robot:displacement()
print(string.format("after 10 s, bent %+.0f deg per yaw joint: x %.3f, y %.3f m", turn.angle, d.x, d.y))
turn.angle = -20                                   -- bend the other way while it runs
sim:run(10)
d = robot:displacement()
print(string.format("after 20 s, bent %+.0f deg per yaw joint: x %.3f, y %.3f m", turn.angle, d.x, d.y))
