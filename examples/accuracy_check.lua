-- examples/accuracy_check.lua: is a result converged? The snake of first_snake.lua, checked
-- before it runs: sim:check_accuracy runs the world again from time 0 at dt / 4 and with 4x
-- the solver iterations and compares the snake's path, sampled once per gait cycle (2 s at
-- 0.5 Hz). A setting that moves it by more than 3 % would be warned, naming the setting; the
-- report says by how much each one moved it (docs/lua-api.md, docs/performance.md "The
-- accuracy check"). `gaitlab check FILE.xml` does the same for a simulation file.
local robot = gaitlab.robot.chain{ name = "snake", modules = 8, connection = "pitch-pitch" }
local world = gaitlab.world{ floor = { friction = 0.8 } }
world:add(robot)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5, phase = 120 })
local sim = gaitlab.simulation{ world = world }

local report = sim:check_accuracy{ seconds = 6, cycle = 2 }  -- three runs of 6 s
local s = report.settings
for _, r in ipairs(report.robots) do
  print(string.format("%s in %g s: %.1f mm at dt %g ms and %d iterations; %.1f mm at dt %g ms"
    .. " (%+.1f %%); %.1f mm with %d iterations (%+.1f %%)", r.name, report.seconds,
    1000 * r.given.path, 1000 * s.given.dt, s.given.solver_iterations, 1000 * r.dt.path,
    1000 * s.dt.dt, r.dt_off, 1000 * r.iterations.path, s.iterations.solver_iterations,
    r.iterations_off))
end
print(#report.warnings == 0 and "converged: within 3 % at both finer settings"
  or #report.warnings .. " setting(s) move it by more than 3 %")

sim:run(20)  -- the simulation itself starts here: the check did not touch it
local d = robot:displacement()
print(string.format("moved %.3f m in %g s", d:norm(), sim.time))
