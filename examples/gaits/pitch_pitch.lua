-- Gait gallery (docs/gaits.md): the travelling wave of an 8-module pitch-pitch worm, as Gonzalez-Gomez's
-- Cube Revolutions robot crawls, and its reversal. With a negative phase the body wave travels from
-- the tail to the head and the worm crawls head first (+x); with the phase's sign flipped the wave
-- and the worm go the other way (docs/conventions.md, "Which way a robot moves").
--
--   gaitlab run examples/gaits/pitch_pitch.lua
local gait = require "gait"

local source = "Gonzalez-Gomez et al., Cube Revolutions (CLAWAR 2004-2006): the 8-module pitch-pitch worm of Y1 modules"
return {
  gait.run{ name = "pp_forward", modules = 8, connection = "pitch-pitch",
            groups = { all = { amplitude = 40, frequency = 0.5, phase = -120 } },
            paper = { source = source,
                      outcome = "the robot moves the way its body wave travels: head first here" } },
  gait.run{ name = "pp_backward", modules = 8, connection = "pitch-pitch",
            groups = { all = { amplitude = 40, frequency = 0.5, phase = 120 } },
            paper = { source = source,
                      outcome = "the wave reversed, the robot reverses: tail first" } },
}
