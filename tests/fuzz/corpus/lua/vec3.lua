-- vectors: arithmetic, comparison, methods, with numbers that are not
local a, b = gaitlab.vec3(1, 2, 3), gaitlab.vec3(0 / 0, 1 / 0, -0.0)
print(a + b, a - b, -a, a * 2, a / 0, a == b, a:dot(b), a:cross(b), a:norm(), a:unpack())
print(pcall(function() return a + 1 end))
print(pcall(function() return a * a end))
print(pcall(function() return "x" .. a end))
print(pcall(gaitlab.vec3, "x", {}, nil))
print(tostring(gaitlab.vec3()), a.x, a.w)
