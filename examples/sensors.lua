-- Sensors: attach one of each kind, read them while a gait runs, switch one off and on.
-- Angles read in degrees; everything else in SI units. See docs/sensors.md.
local robot = gaitlab.robot.chain{ name = "snake", modules = 6, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
world:box{ size = {0.1, 2, 1}, position = {1.0, 0, 0.5} }        -- a wall ahead, face at x = 0.95

local joint = robot:sensor{ kind = "joint", joint = 3 }           -- named "joint3"
local imu = robot:sensor{ kind = "imu", module = 6 }              -- on the head half of module 6
local touch = robot:sensor{ kind = "contact", module = 6 }        -- the whole of module 6
-- a ray looking ahead and 27 degrees up, so the head's rocking does not point it at the floor
local ahead = robot:sensor{ kind = "range", name = "ahead", module = 6,
                            direction = {1, 0, 0.5}, max_range = 2 }
local com = robot:sensor{ kind = "position" }                     -- the centre of mass

robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 30, frequency = 0.5, phase = -120 })
local sim = gaitlab.simulation{ world = world }

for _ = 1, 4 do
  sim:run(0.5)
  local j, i, c, r, p = joint:read(), imu:read(), touch:read(), ahead:read(), com:read()
  print(string.format(
    "t %.1f s  joint3 %6.1f deg  head pitch %6.1f deg az %5.2f m/s²  touching %-5s  wall %.3f m  x %.3f m",
    sim.time, j.angle, i.pitch, i.az, tostring(c.contact), r.distance, p.x))
end

imu:off()                                          -- or imu.enabled = false: no cost while off
sim:run(1)
print("imu switched off, read:", imu:read())       -- nil
imu:on()                                           -- reads again at once
print(string.format("imu on again: head pitch %.1f deg", imu:read().pitch))

for _, s in ipairs(robot:sensors()) do print(s) end
