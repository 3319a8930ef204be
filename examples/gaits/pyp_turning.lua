-- Gait gallery (docs/gaits.md): the turning gait of the 3-module pitch-yaw-pitch robot: the 1D
-- sinusoidal gait with an offset O_H of 40 degrees on the yaw joint, which bends the robot to the
-- left so that it crawls along an arc, turning left.
--
--   gaitlab run examples/gaits/pyp_turning.lua
local gait = require "gait"

return {
  gait.run{ name = "pyp_turning", modules = 3, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = -120 },
                       yaw = { amplitude = 0, frequency = 0.5, phase = 0, offset = 40 } },
            paper = { source = 'Gonzalez-Gomez et al., CLAWAR 2005: the 3-module pitch-yaw-pitch robot, the smallest that does all five gaits',
                      outcome = "a yaw offset O_H makes it turn" } },
}
