-- two recordings into one folder at once
local function make(name)
  local r = gaitlab.robot.chain{ name = name, modules = 2 }
  local w = gaitlab.world{}
  w:add(r)
  return gaitlab.simulation{ world = w, record = "runs/same" }
end
local a = make("a")
a:step(50)
local b = make("b")
b:step(20)
a:step(50)
a:record(false)
b:record(false)
local run = assert(gaitlab.data.open("runs/same"))
print(run.rows, run.status, #run:series(), run:series()[1].name)
local ok, x = pcall(run.get, run, "a.com.x")
print(ok, ok and #x.time or x)
for _, f in ipairs{ "data.csv", "series.csv", "run.json" } do
  local h = io.open("runs/same/" .. f) local s = h:read("a") h:close() print(f, #s, s:sub(1, 60):gsub("\n", "|"))
end
