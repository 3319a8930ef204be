-- required by ../broken.lua: line 3 is not Lua
local t = {
  answer = = 42,
}
return t
