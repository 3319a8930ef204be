-- a sandboxed file whose pattern would take far too long: refused before it runs
local s = string.rep("a", 5000)
return s:find("a*a*a*a*b")
