-- Renders a ready-made world with the standard 8-module snake at its start to a PNG, through
-- gnuplot (pngcairo, `splot ... with polygons`). The geometry comes from world:triangles(), the
-- same solids the physics is built from.
--
--   gaitlab run tools/world_picture.lua NAME OUT.png [SECONDS]
--
-- NAME is a world of gaitlab.worlds; the snake runs a head-first sine gait for SECONDS
-- (default 1.5) so the picture shows it moving. tools/world_pictures.sh makes every picture in
-- docs/images/.
local name, out, seconds = arg[1], arg[2], tonumber(arg[3] or "1.5")
if not (name and out) then
  error("usage: gaitlab run tools/world_picture.lua NAME OUT.png [SECONDS]", 0)
end
local preset = gaitlab.worlds[name]
if not preset then error("no world called '" .. name .. "' in gaitlab.worlds", 0) end

local world, start = preset()
local robot = gaitlab.robot.chain{ name = "snake", modules = 8 }
world:add(robot, start)
robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = 40, frequency = 0.5,
                                                     phase = -120 })
local sim = gaitlab.simulation{ world = world }
sim:run(seconds)

-- Every triangle becomes a degenerate pm3d quadrangle whose colour value is a material band
-- (0 objects, 1 robot, 2 pipes) plus its shade, lit from the viewer's
-- upper left; large triangles are split first so that gnuplot's depth sorting, which compares
-- centres, draws near things over far ones.
-- the camera looks from behind the robot's tail, on its right, 62 degrees down from the
-- vertical (`set view 62, 332`); faces turned away from it are not drawn
local tilt, azimuth = 62, 332
local camera = { math.sin(math.rad(azimuth)) * math.sin(math.rad(tilt)),
                 -math.cos(math.rad(azimuth)) * math.sin(math.rad(tilt)), math.cos(math.rad(tilt)) }
-- the light comes from the camera's left and above: treads lighter than risers
local light = { -0.42, -0.5, 0.76 }
local max_edge = 0.08  -- m
local tmp = os.tmpname()
local files = { solid = tmp .. ".solid" }
local handles = { solid = assert(io.open(files.solid, "w")) }
local count = { solid = 0 }
local lo = { x = math.huge, y = math.huge }
local hi = { x = -math.huge, y = -math.huge, z = -math.huge }

-- the unit normal of a triangle whose corners are counter-clockwise seen from outside
local function normal(a, b, c)
  local ux, uy, uz = b[1] - a[1], b[2] - a[2], b[3] - a[3]
  local vx, vy, vz = c[1] - a[1], c[2] - a[2], c[3] - a[3]
  local nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
  local n = math.sqrt(nx * nx + ny * ny + nz * nz)
  if n == 0 then return nil end
  return { nx / n, ny / n, nz / n }
end

local function dot(u, v) return u[1] * v[1] + u[2] * v[2] + u[3] * v[3] end

-- ambient plus diffuse light, squeezed inside the material's band
local function shade(n)
  return 0.04 + 0.92 * (0.3 + 0.7 * math.max(0, dot(n, light)))
end

local function emit(group, band, a, b, c, s)
  local f = handles[group]
  local v = band + s
  f:write(string.format("%.5f %.5f %.5f %.4f\n%.5f %.5f %.5f %.4f\n\n", a[1], a[2], a[3], v,
    b[1], b[2], b[3], v))
  f:write(string.format("%.5f %.5f %.5f %.4f\n%.5f %.5f %.5f %.4f\n\n\n", c[1], c[2], c[3], v,
    c[1], c[2], c[3], v))
  count[group] = count[group] + 1
end

-- splits a triangle at the middle of its longest edge until every edge is short
local function split(group, band, a, b, c, s)
  local function d2(p, q) return (p[1] - q[1]) ^ 2 + (p[2] - q[2]) ^ 2 + (p[3] - q[3]) ^ 2 end
  local ab, bc, ca = d2(a, b), d2(b, c), d2(c, a)
  local longest = math.max(ab, bc, ca)
  if longest <= max_edge ^ 2 then return emit(group, band, a, b, c, s) end
  if bc == longest then a, b, c = b, c, a elseif ca == longest then a, b, c = c, a, b end
  local m = { (a[1] + b[1]) / 2, (a[2] + b[2]) / 2, (a[3] + b[3]) / 2 }
  split(group, band, a, m, c, s)
  split(group, band, m, b, c, s)
end

local solids = world:triangles()

-- a pipe is drawn cut open: the walls on the camera's side of its axis are left out. Each wall
-- spans the pipe's length, so the centre of a pipe's walls is on its axis, and a wall's centre
-- minus that is its outward direction.
local function centre(list)
  local c, n = { 0, 0, 0 }, 0
  for _, solid in ipairs(list) do
    local v = solid.vertices
    for i = 1, #v, 3 do c[1], c[2], c[3], n = c[1] + v[i], c[2] + v[i + 1], c[3] + v[i + 2], n + 1 end
  end
  return { c[1] / n, c[2] / n, c[3] / n }
end
local walls = {}
for _, solid in ipairs(solids) do
  if solid.kind == "pipe" then
    walls[solid.object] = walls[solid.object] or {}
    table.insert(walls[solid.object], solid)
  end
end
local axis = {}
for object, list in pairs(walls) do axis[object] = centre(list) end

for _, solid in ipairs(solids) do
  local band = solid.kind == "robot" and 1 or solid.kind == "pipe" and 2 or 0
  local cut = false
  if band == 2 then
    local c, a = centre({ solid }), axis[solid.object]
    cut = dot({ c[1] - a[1], c[2] - a[2], c[3] - a[3] }, camera) > 0
  end
  local v = solid.vertices
  for i = 1, cut and 0 or #v, 9 do
    local a = { v[i], v[i + 1], v[i + 2] }
    local b = { v[i + 3], v[i + 4], v[i + 5] }
    local c = { v[i + 6], v[i + 7], v[i + 8] }
    for _, p in ipairs{ a, b, c } do
      lo.x, lo.y = math.min(lo.x, p[1]), math.min(lo.y, p[2])
      hi.x, hi.y, hi.z = math.max(hi.x, p[1]), math.max(hi.y, p[2]), math.max(hi.z, p[3])
    end
    local n = normal(a, b, c)
    if n and dot(n, camera) > 0 then split("solid", band, a, b, c, shade(n)) end
  end
end
-- the floor: a rectangle under everything, a little larger than the scene, drawn behind the
-- surfaces (nothing is below it)
local margin = 0.15
lo.x, lo.y, hi.x, hi.y = lo.x - margin, lo.y - margin, hi.x + margin, hi.y + margin
-- its colour goes from icy blue (friction 0) to sage green (friction 1)
local mu = preset.params.friction and preset.params.friction[1] or 0.8
local function mix(from, to) return math.floor(from + (to - from) * mu + 0.5) end
local floor = string.format("set object 1 polygon from %f,%f,0 to %f,%f,0 to %f,%f,0 to " ..
  "%f,%f,0 to %f,%f,0 fillstyle solid 1.0 noborder fc rgb '#%02x%02x%02x' behind", lo.x, lo.y,
  hi.x, lo.y, hi.x, hi.y, lo.x, hi.y, lo.x, lo.y, mix(0xd4, 0xb5), mix(0xe9, 0xc6),
  mix(0xf7, 0xa3))
for _, f in pairs(handles) do f:close() end

-- equal scales on every axis; the z range at least 0.3 m so flat worlds do not look tall
local span = math.max(hi.x - lo.x, hi.y - lo.y)
local top = math.max(hi.z, 0.3)
local plots = { string.format("'%s' using 1:2:3:4 with pm3d", files.solid) }
local script = table.concat({
  "set terminal pngcairo size 900,560 enhanced font 'DejaVu Sans,11'",
  string.format("set output '%s'", out),
  string.format("set title \"gaitlab.worlds.%s{}: friction %g, 8-module snake %g s into a " ..
    "head-first gait%s\" noenhanced", name, mu, seconds, next(walls) and " (pipe cut open)" or ""),
  string.format("set view %d, %d, 1.75", tilt, azimuth),
  "set view equal xyz",
  string.format("set xrange [%f:%f]", lo.x, lo.x + span),
  string.format("set yrange [%f:%f]", (lo.y + hi.y - span) / 2, (lo.y + hi.y + span) / 2),
  string.format("set zrange [0:%f]", top),
  "set xlabel 'x (m)'", "set ylabel 'y (m)'",
  "set xtics 0.5", "set ytics 0.5", "set ztics 0.1",
  "set xyplane at 0",
  floor,
  "set pm3d depthorder noborder",
  -- bands: objects (sandstone), robot (orange), pipes (steel blue)
  "set palette defined (0 '#4f483b', 1 '#f3ecdc', 1.0001 '#5e1a04', 2 '#ffab70', " ..
    "2.0001 '#22405c', 3 '#c9e2f6')",
  "set cbrange [0:3]",
  "unset key", "unset colorbox",
  "splot " .. table.concat(plots, ", "),
}, "\n")
local gnuplot = assert(io.popen("gnuplot", "w"))
gnuplot:write(script, "\n")
local ok = gnuplot:close()
for _, path in pairs(files) do os.remove(path) end
os.remove(tmp)
if not ok then error("gnuplot failed to draw " .. out, 0) end
print(string.format("%s: %d triangles", out, count.solid))
