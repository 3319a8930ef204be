-- Runs until a signal stops it: a simulation stepping in C++ with a Lua controller, for as long
-- as it takes. arg[1] = "catch": the script sets a debug hook of its own, catches the interrupt
-- and goes on.
local robot = gaitlab.robot.chain{ name = "snake", modules = 4 }
local world = gaitlab.world()
world:add(robot)
local running = false
robot:group("pitch"):drive(gaitlab.controller{ name = "busy", step = function(self)
  -- said from inside sim:run, so that the signal the tests send then finds it running
  if not running then io.stderr:write("running\n") running = true end
  for m = 1, self.joints do self:set_angle(m, 10) end
end }())
-- recorded where INTERRUPT_RECORD names a folder (the lua5.4 run): closed as "interrupted"
local sim = gaitlab.simulation{ world = world, record = os.getenv("INTERRUPT_RECORD") or false }
if arg[1] == "catch" then
  local function hook() end
  debug.sethook(hook, "", 1000000000)
  local ok, err = pcall(sim.run, sim, 1e6)
  print("caught:", ok, err)
  print("runs again:", pcall(sim.run, sim, 0.1))
  print("hook kept:", debug.gethook() == hook)
else
  sim:run(1e6)
end
