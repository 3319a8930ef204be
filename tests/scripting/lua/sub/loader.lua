-- loads a controller relative to this file's folder (tests/scripting/lua/sub)
return gaitlab.controller.load("../counter.lua")
