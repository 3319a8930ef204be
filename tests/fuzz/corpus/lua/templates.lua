-- the built-in controller templates: used as they are, and copied into files to load
for _, name in ipairs(gaitlab.controller.templates()) do print(name) end
local Sine = gaitlab.controller.template("sine")
local Cpg = gaitlab.controller.template("cpg_chain")
local Blank = gaitlab.controller.template("blank")
print(pcall(gaitlab.controller.template, "nope"))
print(gaitlab.controller.write_template("blank", "mine.lua"))
print(gaitlab.controller.write_template("blank", "mine.lua"))
print(gaitlab.controller.write_template("sine", "ctl/sine.lua"))
local Mine = gaitlab.controller.load("mine.lua")
local robot = gaitlab.robot.chain{ modules = 6 }
local world = gaitlab.world{}
world:add(robot)
robot:group{ 1, 2 }:drive(Sine{ amplitude = 30 })
robot:group{ 3, 4 }:drive(Cpg())
robot:group{ 5 }:drive(Blank())
robot:group{ 6 }:drive(Mine())
gaitlab.simulation{ world = world }:step(100)
