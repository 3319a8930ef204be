-- Gait gallery (docs/gaits.md): the lateral shift of the 3-module pitch-yaw-pitch robot: both pitch
-- joints in phase, the yaw joint 90 degrees ahead of them, 40 degrees each: the body does not roll
-- over but shuffles sideways.
--
--   gaitlab run examples/gaits/pyp_lateral_shift.lua
local gait = require "gait"

return {
  gait.run{ name = "pyp_lateral_shift", modules = 3, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = 0 },
                       yaw = { amplitude = 40, frequency = 0.5, phase = 0, phase0 = 90 } },
            paper = { source = 'Gonzalez-Gomez et al., CLAWAR 2005: the 3-module pitch-yaw-pitch robot, the smallest that does all five gaits',
                      outcome = "it moves sideways" } },
}
