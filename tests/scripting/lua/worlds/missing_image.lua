-- a heightfield naming an image that does not exist next to this file
local w = gaitlab.world()
w:heightfield{ image = "no_such_terrain.png", max_height = 0.1 }
