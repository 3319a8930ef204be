-- a sandboxed file that asks for a finalizer: refused
return setmetatable({}, { __gc = function() end })
