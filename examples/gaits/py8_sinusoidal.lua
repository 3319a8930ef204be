-- Gait gallery (docs/gaits.md): the 1D sinusoidal gait of the 8-module pitch-yaw robot. Only the
-- pitch joints wave (a travelling wave, tail to head); the yaw joints stay straight, so it crawls
-- along its body axis like a pitch-pitch worm.
--
--   gaitlab run examples/gaits/py8_sinusoidal.lua
local gait = require "gait"

return {
  gait.run{ name = "py8_sinusoidal", modules = 8, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = -120 } },
            paper = { source = 'Gonzalez-Gomez, Zhang, Boemo, Zhang, "Locomotion capabilities of a modular robot with eight pitch-yaw-connecting modules", CLAWAR 2006',
                      outcome = "yaw joints still: it moves along its body axis, the way the wave travels" } },
}
