-- Gait gallery (docs/gaits.md): the turning gait of the 8-module pitch-yaw robot: the 1D
-- sinusoidal gait with an offset O_H on the yaw joints (a yaw "sine" of amplitude 0 and offset 20
-- degrees), which bends the body into an arc that it then crawls along: a positive offset bends
-- it to the left (counter-clockwise), and it turns left.
--
--   gaitlab run examples/gaits/py8_turning.lua
local gait = require "gait"

return {
  gait.run{ name = "py8_turning", modules = 8, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = -120 },
                       yaw = { amplitude = 0, frequency = 0.5, phase = 0, offset = 20 } },
            paper = { source = 'Gonzalez-Gomez, Zhang, Boemo, Zhang, "Locomotion capabilities of a modular robot with eight pitch-yaw-connecting modules", CLAWAR 2006',
                      outcome = "a yaw offset O_H makes it turn" } },
}
