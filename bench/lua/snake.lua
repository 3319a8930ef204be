-- The benchmark snake as a gaitlab script, for whole-process timings (bench/run.sh):
--   gaitlab run bench/lua/snake.lua MODULES CONNECTION CONTROL_EVERY CONTROLLER [SECONDS]
-- CONNECTION is pp or py; CONTROLLER is "sine" (the built-in C++ sine) or the path of a Lua
-- controller file with amplitude, frequency and phase (examples/controllers/my_sine.lua).
local modules = tonumber(arg[1] or "8")
local connection = (arg[2] or "pp") == "py" and "pitch-yaw" or "pitch-pitch"
local control_every = tonumber(arg[3] or "10")
local controller = arg[4] or "sine"
local seconds = tonumber(arg[5] or "20")

local make = controller == "sine" and gaitlab.controllers.sine
    or gaitlab.controller.load(controller)

local robot = gaitlab.robot.chain{ name = "snake", modules = modules, connection = connection }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(make{ amplitude = 40, frequency = 0.5, phase = 120 })
if connection == "pitch-yaw" then
  robot:group("yaw"):drive(make{ amplitude = 20, frequency = 0.5, phase = 120 })
end
local sim = gaitlab.simulation{ world = world, dt = 0.001, control_every = control_every,
                                record = false }
sim:run(seconds)
local d = robot:displacement()
print(string.format("%s %d %s: dx %.6f dy %.6f", controller, modules, connection, d.x, d.y))
