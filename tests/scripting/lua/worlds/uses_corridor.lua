-- loads corridor.lua by a path relative to this file
corridor_world, corridor_start = gaitlab.world.load("corridor.lua"){ gap = 0.3 }
