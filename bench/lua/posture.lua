-- A robot's posture, shared by the bench scripts (docs/performance.md, section 12, "Upright or
-- on its side"): the bodies' mean tilt, the angle between each body's z axis and the world's,
-- in degrees (0 upright, 90 on their side, 180 upside down). It tells a long pitch-yaw chain's
-- two wave motions apart: upright, or lying twisted on its side.
--
--   local tilt = require "posture"
--   tilt(robot)  --> 21.3
return function(robot)
  local bodies, sum = robot:bodies(), 0
  for _, b in ipairs(bodies) do
    local q = b.orientation  -- the body's z in the world: its z component is 1 - 2 (x² + y²)
    sum = sum + math.deg(math.acos(math.max(-1, math.min(1, 1 - 2 * (q.x * q.x + q.y * q.y)))))
  end
  return sum / #bodies
end
