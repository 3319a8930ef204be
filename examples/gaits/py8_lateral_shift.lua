-- Gait gallery (docs/gaits.md): the lateral shift of the 8-module pitch-yaw robot: travelling
-- waves in both planes (phase 100 degrees between neighbours of a plane, the yaw wave 90 degrees
-- ahead of the pitch wave), a side-winding-like gait that moves the robot sideways without
-- rolling it.
--
--   gaitlab run examples/gaits/py8_lateral_shift.lua
local gait = require "gait"

return {
  gait.run{ name = "py8_lateral_shift", modules = 8, connection = "pitch-yaw",
            groups = { pitch = { amplitude = 40, frequency = 0.5, phase = 100 },
                       yaw = { amplitude = 40, frequency = 0.5, phase = 100, phase0 = -90 } },
            paper = { source = 'Gonzalez-Gomez, Zhang, Boemo, Zhang, "Locomotion capabilities of a modular robot with eight pitch-yaw-connecting modules", CLAWAR 2006',
                      outcome = "side-winding-like travelling waves in both planes: it moves sideways" } },
}
