-- Gait gallery (docs/gaits.md): the rotating gait of the 8-module pitch-yaw robot: different phase
-- differences in the two planes (180 degrees between pitch joints, a standing wave of small
-- amplitude; 90 degrees between yaw joints), which turns the robot about its vertical axis almost
-- on the spot.
--
--   gaitlab run examples/gaits/py8_rotating.lua
local gait = require "gait"

return {
  gait.run{ name = "py8_rotating", modules = 8, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 20, frequency = 0.5, phase = 180 },
                       yaw = { amplitude = 40, frequency = 0.5, phase = 90 } },
            paper = { source = 'Gonzalez-Gomez, Zhang, Boemo, Zhang, "Locomotion capabilities of a modular robot with eight pitch-yaw-connecting modules", CLAWAR 2006',
                      outcome = "different phase differences in the two planes: it rotates in place" } },
}
