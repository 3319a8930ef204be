-- a controller file that forgets to return its class
local _ = gaitlab.controller{ name = "forgotten", step = function() end }
