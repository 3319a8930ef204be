-- Bad input to every part of the API, each caught and printed, then one that is not caught:
-- the messages (and that nothing leaks or crashes on the C core) are what the tests compare.
-- Argument tables with metamethods that raise: gaitlab reads them raw, so the metamethods never
-- run in the middle of a binding.
local function try(what, fn, ...)
  print(what, pcall(fn, ...))
end
local raising = setmetatable({}, { __index = function() error("index metamethod ran") end,
                                   __newindex = function() error("newindex metamethod ran") end,
                                   __len = function() error("len metamethod ran") end,
                                   __pairs = function() error("pairs metamethod ran") end })

try("chain", gaitlab.robot.chain, { modules = 0 })
try("chain key", gaitlab.robot.chain, { modules = 4, conection = "pitch-yaw" })
try("chain type", gaitlab.robot.chain, "snake")
try("chain raising", gaitlab.robot.chain, raising)
try("world raising", gaitlab.world, raising)
try("world floor", gaitlab.world, { floor = 3 })
local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
try("group", robot.group, robot, "sideways")
try("group list", robot.group, robot, { 1, 1 })
try("group raising", robot.group, robot, raising)
try("sensor", robot.sensor, robot, { kind = "imu", module = 9 })
try("sensor kind", robot.sensor, robot, { kind = "radar" })
try("sensor name", robot.sensor, robot, "nose")
try("not in a simulation", robot.position, robot)
try("module", gaitlab.module, { name = "box", length = -1 })
try("module base", gaitlab.module, { name = "odd", base = "no such module" })
local world = gaitlab.world()
try("box", world.box, world, { size = { 1, 2 } })
try("add twice", function() world:add(robot) world:add(robot) end)
try("heightfield rows", world.heightfield, world, { heights = { { 1, 2 }, { 3 } } })
try("heightfield function", world.heightfield, world,
    { samples = { 3, 3 }, heights = function(x, y) if x > 0 then error("no height here") end return 0 end })
try("controller params", gaitlab.controllers.sine, { amplitude = 500 })
try("controller unknown", gaitlab.controllers.sine, { amplitde = 5 })
try("controller class", gaitlab.controller, { name = "c", step = print, values = raising })
try("controller class params", gaitlab.controller, { name = "c", step = print, params = { gain = { 1 } } })
try("controller reserved", gaitlab.controller, { name = "c", step = print, values = { "joints" } })
local sine = gaitlab.controllers.sine{}
try("param set", function() sine.amplitude = "loud" end)
try("param get", function() return sine.amplitud end)
try("load missing", gaitlab.controller.load, "no/such/file.lua")
try("load not a class", gaitlab.controller.load, "controllers/not_a_class.lua")
try("template", gaitlab.controller.template, "sinus")
try("simulation world", gaitlab.simulation, { world = 5 })
try("simulation record", gaitlab.simulation, { world = world, record = { series = raising } })
try("simulation policy", gaitlab.simulation, { world = world, on_controller_error = "panic" })
local sim = gaitlab.simulation{ world = world }
try("run", sim.run, sim, -1)
try("step", sim.step, sim, 1.5)
try("speed", function() sim.speed = 0 end)
try("read only", function() sim.time = 3 end)
try("save", sim.save, sim, "out.xml", { duration = -2 })
try("load file", gaitlab.simulation.load, "no_such_file.xml")
try("data", gaitlab.data.open, "no_such_run")
try("live", sim.live, sim, { sample_every = 0 })
try("actuation", gaitlab.actuation.load, "no_such.actuation.xml")
-- a Lua controller's own methods: outside its step, and with bad arguments inside it
local stepped
local Probe = gaitlab.controller{ name = "probe", values = { "seen" }, step = function(self)
  stepped = self
  local ok, err = pcall(self.set_angle, self, 99, 10)
  self.seen[1] = ok and 1 or 0
  if not ok then io.write("set_angle: ", err, "\n") end
  ok, err = pcall(self.sensor, self, "nose")
  if not ok then io.write("sensor: ", err, "\n") end
  ok, err = pcall(self.set_angle, self, 1, 0 / 0)
  if not ok then io.write("nan: ", err, "\n") end
end }
local probe = Probe{}
robot:group{ 1 }:drive(probe)
sim:step(30)
try("method outside step", stepped.set_angle, stepped, 1, 0)
try("method of a controller that is gone", function()
  sim = nil robot = nil probe = nil world = nil collectgarbage() collectgarbage()
  return stepped:joint_angle(1)
end)
-- sandboxed controller files: a costly pattern, a finalizer, a protected metatable
try("sandbox pattern", gaitlab.controller.load, "controllers/pattern.lua")
try("sandbox gc", gaitlab.controller.load, "controllers/finalizer.lua")
-- the module library cannot be given metamethods, nor written but by gaitlab.module
try("module library metatable", setmetatable, gaitlab.modules,
    { __index = function() error("modules metamethod ran") end })
try("module library write", function() gaitlab.modules.cube = nil end)
-- module names longer than a short string: a binding that an error jumped out of would leak
-- their copies, which leak checkers see
try("module name", gaitlab.robot.chain, { modules = 2, module = "a module type nobody defined" })
try("module new", gaitlab.module, { name = "a plank of wood, 10 cm long", length = 0.1 })
print(gaitlab.modules["a plank of wood, 10 cm long"] ~= nil)
-- and one error nobody catches
gaitlab.robot.chain{ modules = 4, connection = "diagonal" }
