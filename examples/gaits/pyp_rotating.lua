-- Gait gallery (docs/gaits.md): the rotating gait of the 3-module pitch-yaw-pitch robot: the two
-- pitch joints in opposition (20 degrees, 180 degrees apart), the yaw joint waving 60 degrees, 90
-- degrees ahead of the first pitch joint; the robot turns about its vertical axis almost on the
-- spot.
--
--   gaitlab run examples/gaits/pyp_rotating.lua
local gait = require "gait"

return {
  gait.run{ name = "pyp_rotating", modules = 3, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 20, frequency = 0.5, phase = 180 },
                       yaw = { amplitude = 60, frequency = 0.5, phase = 0, phase0 = 90 } },
            paper = { source = 'Gonzalez-Gomez et al., CLAWAR 2005: the 3-module pitch-yaw-pitch robot, the smallest that does all five gaits',
                      outcome = "different phase differences in the two planes: it rotates in place" } },
}
