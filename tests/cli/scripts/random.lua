-- prints a few draws of math.random
local t = {}
for i = 1, 4 do t[i] = math.random(1000000) end
print(table.concat(t, " "))
