-- Draws docs/gaits.md's pictures and measures its table: runs every gait of examples/gaits/ with
-- each simulation recorded into a run folder, plots the path of its centre of mass seen from above
-- (gaitlab's path plot, run:plot{ x =, y = }, as `gaitlab data RUN --xy X Y --plot OUT.png` draws
-- it) into OUT_DIR/NAME.png, and prints the table of what it measured as Markdown.
--
--   gaitlab run tools/gait_pictures.lua [OUT_DIR [CYCLES]]      (default docs/images/gaits, 10)
local here = debug.getinfo(1, "S").source:match("^@(.*)/") or "."
local root = here .. "/.."
local out = arg[1] or (root .. "/docs/images/gaits")
local cycles = math.tointeger(tonumber(arg[2] or "10"))
if not cycles or cycles < 1 then error("CYCLES must be an integer of at least 1 (got " .. tostring(arg[2]) .. ")") end

package.path = root .. "/examples/gaits/?.lua;" .. package.path
local gait = require "gait"
local runs = os.tmpname()
os.remove(runs)
gait.options.record = runs
gait.options.cycles = cycles
gait.options.quiet = true

local examples = { "pitch_pitch", "py8_sinusoidal", "py8_turning", "py8_rolling", "py8_lateral_shift",
                   "py8_rotating", "pyp_sinusoidal", "pyp_turning", "pyp_rolling", "pyp_lateral_shift",
                   "pyp_rotating" }

local function copy(from, to)
  local i = assert(io.open(from, "rb"))
  local data = i:read("a")
  i:close()
  local o = assert(io.open(to, "wb"))
  o:write(data)
  o:close()
end

local function params(m)
  local parts = {}
  for _, group in ipairs{ "all", "pitch", "yaw" } do
    local p = m.params[group]
    if p then
      local s = string.format("%s %g°", group, p.amplitude or 40)
      if (p.amplitude or 40) > 0 then s = s .. string.format(" Δφ %g°", p.phase or 120) end
      if (p.phase0 or 0) ~= 0 then s = s .. string.format(" φ0 %g°", p.phase0) end
      if (p.offset or 0) ~= 0 then s = s .. string.format(" O %g°", p.offset) end
      parts[#parts + 1] = s
    end
  end
  return table.concat(parts, ", ")
end

print(string.format("%d cycles of 2 s after 1, friction 1.0, dt 1 ms, control every 10 ms", cycles))
print("| gait | robot | sines | along (mm/cycle) | across (mm/cycle) | turn (deg/cycle) | roll (deg/cycle) | path |")
print("|---|---|---|---|---|---|---|---|")
for _, example in ipairs(examples) do
  for _, m in ipairs(dofile(root .. "/examples/gaits/" .. example .. ".lua")) do
    m.sim:record(false)
    local run = assert(gaitlab.data.open(runs .. "/" .. m.name))
    local png = run:plot{ x = m.name .. ".com.x", y = m.name .. ".com.y", output = runs .. "/" .. m.name .. ".png",
                          title = m.name .. ": centre of mass from above, " .. (cycles + 1) .. " cycles" }
    copy(png, out .. "/" .. m.name .. ".png")
    local chain = m.robot.chain
    -- what is not the gallery's usual: another frequency than 0.5 Hz, another floor
    local extra = m.frequency ~= 0.5 and string.format(", %g Hz", m.frequency) or ""
    local floor = gait.floor_text(m.floor)
    if floor then extra = extra .. ", " .. floor end
    print(string.format("| %s | %d %s | %s%s | %+.1f | %+.1f | %+.1f | %+.1f | ![](images/gaits/%s.png) |", m.name,
                        chain.modules, chain.connection, params(m), extra, m.along, m.across, m.turn, m.roll, m.name))
  end
end
os.execute("rm -rf '" .. runs:gsub("'", "'\\''") .. "'")
