-- Gait gallery (docs/gaits.md): the rolling gait of the 3-module pitch-yaw-pitch robot: both pitch
-- joints in phase, the yaw joint 90 degrees behind them, 60 degrees each. The body's arc turns
-- about its axis once a cycle, so it rolls about its body axis and moves sideways. (At 40 degrees
-- the same pattern does not roll: it is the lateral shift, pyp_lateral_shift.lua.)
--
--   gaitlab run examples/gaits/pyp_rolling.lua
local gait = require "gait"

return {
  gait.run{ name = "pyp_rolling", modules = 3, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 60, frequency = 0.5, phase = 0 },
                       yaw = { amplitude = 60, frequency = 0.5, phase = 0, phase0 = -90 } },
            paper = { source = 'Gonzalez-Gomez et al., CLAWAR 2005: the 3-module pitch-yaw-pitch robot, the smallest that does all five gaits',
                      outcome = "all joints in phase, yaw 90 deg from pitch, large amplitudes: it rolls about its body axis" } },
}
