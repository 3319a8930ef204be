-- gaitlab.Vec3: the vectors the engine returns ({x = , y = , z = }), with arithmetic and norm.
local gaitlab, registry = ...
local mt = registry["gaitlab.Vec3"]
local sqrt = math.sqrt

local function vec3(x, y, z)
  return setmetatable({ x = x or 0, y = y or 0, z = z or 0 }, mt)
end

local methods = {}

--- Euclidean length.
function methods.norm(v) return sqrt(v.x * v.x + v.y * v.y + v.z * v.z) end
function methods.dot(a, b) return a.x * b.x + a.y * b.y + a.z * b.z end
function methods.cross(a, b)
  return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)
end
--- x, y, z as three values.
function methods.unpack(v) return v.x, v.y, v.z end

mt.__name = "gaitlab.Vec3"
mt.__index = methods
mt.__add = function(a, b) return vec3(a.x + b.x, a.y + b.y, a.z + b.z) end
mt.__sub = function(a, b) return vec3(a.x - b.x, a.y - b.y, a.z - b.z) end
mt.__unm = function(a) return vec3(-a.x, -a.y, -a.z) end
mt.__mul = function(a, b)
  if type(a) == "number" then a, b = b, a end
  return vec3(a.x * b, a.y * b, a.z * b)
end
mt.__div = function(a, s) return vec3(a.x / s, a.y / s, a.z / s) end
mt.__eq = function(a, b) return a.x == b.x and a.y == b.y and a.z == b.z end
mt.__tostring = function(v) return string.format("(%.6g, %.6g, %.6g)", v.x, v.y, v.z) end

gaitlab.vec3 = vec3
