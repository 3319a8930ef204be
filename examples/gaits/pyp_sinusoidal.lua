-- Gait gallery (docs/gaits.md): the 1D sinusoidal gait of the 3-module pitch-yaw-pitch robot: its
-- two pitch joints wave 120 degrees apart (the wave travels tail to head), the yaw joint stays
-- straight; it crawls along its body axis, head first.
--
--   gaitlab run examples/gaits/pyp_sinusoidal.lua
local gait = require "gait"

return {
  gait.run{ name = "pyp_sinusoidal", modules = 3, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = -120 } },
            paper = { source = 'Gonzalez-Gomez et al., CLAWAR 2005: the 3-module pitch-yaw-pitch robot, the smallest that does all five gaits',
                      outcome = "yaw joint still: it moves along its body axis, the way the wave travels" } },
}
