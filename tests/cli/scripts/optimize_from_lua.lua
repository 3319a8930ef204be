-- gaitlab.optimize{...} on optimize_small.lua (found beside this script) into the folder arg[1]
local r = gaitlab.optimize{ spec = "optimize_small.lua", out = arg[1] }
print("best", r.fitness, r.evaluations)
