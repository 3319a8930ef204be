-- The peer engines' snake (the performance anchors' workload) built with gaitlab's public Lua
-- API, so that gaitlab steps exactly the robot, servo law and gait that ODE and MuJoCo step there
-- (bench/anchors.sh runs them side by side; docs/performance.md, section 12):
--
--   gaitlab run bench/lua/anchor_snake.lua [n=8] [conn=pp|py] [dt=0.001] [iters=20] [ce=10]
--       [time=20] [phase0=0] [trace=0] [solver=pgs|block_nncg] [rigid=0|1] [floor_k=N/m]
--       [floor_c=N s/m] --no-record
--
-- The robot: n solid boxes of 72 x 52 x 52 mm and 50 g in a row (not gaitlab's y1 module, whose
-- chain has n + 1 bodies), head (module 0) at x = 0, the chain towards -x, n - 1 hinges through
-- the centres of the shared faces; pitch-pitch, or pitch (head joint) and yaw alternating. Floor
-- friction 0.8. Servo: v = clamp(20 (target - angle), +-5.2 rad/s), at most 0.3 N m. Gait: every
-- ce steps, target of the k-th joint of a group counted from the head = A sin(2 pi 0.5 t + k 120
-- deg + phase0), A = 40 deg (pitch) and 20 deg (yaw), t counted from 0 at the first step.
--
-- Prints one line of key=value pairs as the anchors' programs do: cpu_us_per_step is the
-- process CPU time of the stepping alone (os.clock) per step; trace = the head's x,y (m) every
-- `trace` simulated seconds from the start, and at the end, separated by ';'. solver: the
-- simulation's constraint solver (gaitlab.simulation's `solver`); left out, the engine's default
-- (block_nncg), and the line does not name it; given, the settings field ends with ",solver=NAME".
-- The floor is the engine's default (compliant: 3e3 N/m and 60 N s/m per contact point) unless
-- rigid=1 (a rigid floor; the settings field then ends with ",floor=rigid") or floor_k /
-- floor_c (its stiffness and damping) say otherwise.
local opt = { n = 8, conn = "pp", dt = 0.001, iters = 20, ce = 10, time = 20, phase0 = 0,
              trace = 0, solver = false, floor_k = false, floor_c = false, rigid = 0 }
local solvers = { pgs = true, block_nncg = true }
for _, a in ipairs(arg) do
  local k, v = a:match("^([%w_]+)=(.+)$")
  if not k or opt[k] == nil then
    error(string.format("anchor_snake.lua: unknown argument '%s' (expected KEY=VALUE with KEY "
                        .. "one of n, conn, dt, iters, ce, time, phase0, trace, solver, floor_k, floor_c, rigid)", a), 0)
  end
  if k == "conn" then
    if v ~= "pp" and v ~= "py" then
      error("anchor_snake.lua: conn must be pp or py (got '" .. v .. "')", 0)
    end
    opt.conn = v
  elseif k == "solver" then
    if not solvers[v] then
      error("anchor_snake.lua: solver must be pgs or block_nncg (got '" .. v .. "')", 0)
    end
    opt.solver = v
  else
    local x = tonumber(v)
    if not x then
      error(string.format("anchor_snake.lua: %s must be a number (got '%s')", k, v), 0)
    end
    opt[k] = x
  end
end
if opt.n < 2 or opt.n % 1 ~= 0 then error("anchor_snake.lua: n must be an integer >= 2", 0) end

local len, width, mass = 0.072, 0.052, 0.05
local pitch_yaw = opt.conn == "py"
local bodies, joints = {}, {}
for i = 0, opt.n - 1 do
  bodies[#bodies + 1] = { name = "m" .. i, size = { len, width, width }, mass = mass,
                          position = { -i * len, 0, width / 2 } }
end
-- joint j joins module j (head side, the parent) and module j + 1; listed from the head, so the
-- k-th joint of a group is the k-th of its role in this list, as in the anchors
for j = 0, opt.n - 2 do
  local yaw = pitch_yaw and j % 2 == 1
  joints[#joints + 1] = { name = "j" .. j, role = yaw and "yaw" or "pitch",
                          parent = "m" .. j, child = "m" .. (j + 1),
                          pivot = { -j * len - len / 2, 0, width / 2 },
                          axis = yaw and { 0, 0, 1 } or { 0, 1, 0 },
                          min = -90, max = 90,
                          kp = 20, max_speed = math.deg(5.2), max_torque = 0.3 }
end
local robot = gaitlab.robot.new{ name = "snake", bodies = bodies, joints = joints }
if opt.rigid ~= 0 and opt.rigid ~= 1 then error("anchor_snake.lua: rigid must be 0 or 1", 0) end
local floor = { friction = 0.8, rigid = opt.rigid == 1 or nil, stiffness = opt.floor_k or nil,
                damping = opt.floor_c or nil }
local world = gaitlab.world{ floor = floor }
world:add(robot)

-- gaitlab's sine computes its first target at t = ce * dt; the anchors' at t = 0
local f = 0.5
local lead = 360 * f * opt.ce * opt.dt
local function phase0(extra)
  local p = (opt.phase0 + extra - lead + 180) % 360 - 180
  return p
end
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = f, phase = 120,
                                                     phase0 = phase0(0) })
if pitch_yaw then
  robot:group("yaw"):drive(gaitlab.controllers.sine{ amplitude = 20, frequency = f, phase = 120,
                                                     phase0 = phase0(0) })
end
local sim = gaitlab.simulation{ world = world, dt = opt.dt, control_every = opt.ce,
                                solver_iterations = opt.iters, solver = opt.solver or nil,
                                record = false }
local r = sim:robot("snake")

local function head()
  local b = r:bodies()[1]
  assert(b.name == "m0")
  return b.position
end

local steps = math.floor(opt.time / opt.dt + 0.5)
local chunk = opt.trace > 0 and math.floor(opt.trace / opt.dt + 0.5) or steps
local trace = {}
local h0 = head()
local cpu = 0
local done = 0
while done < steps do
  if opt.trace > 0 then
    local p = head()
    trace[#trace + 1] = string.format("%.7f,%.7f", p.x, p.y)
  end
  local n = math.min(chunk, steps - done)
  local c0 = os.clock()
  sim:step(n)
  cpu = cpu + (os.clock() - c0)
  done = done + n
end
local h1 = head()
if opt.trace > 0 and steps % chunk == 0 then
  trace[#trace + 1] = string.format("%.7f,%.7f", h1.x, h1.y)
end
print(string.format("engine=gaitlab conn=%s n=%d steps=%d sim_s=%.3f head_dx=%.4f head_dy=%.4f "
                    .. "settings=iters=%d,dt=%g,ce=%d%s%s cpu_us_per_step=%.3f trace=%s",
                    opt.conn, opt.n, steps, steps * opt.dt, h1.x - h0.x, h1.y - h0.y, opt.iters,
                    opt.dt, opt.ce, opt.solver and ",solver=" .. opt.solver or "",
                    floor.rigid and ",floor=rigid" or "",
                    cpu / steps * 1e6,
                    #trace > 0 and table.concat(trace, ";") or "-"))
