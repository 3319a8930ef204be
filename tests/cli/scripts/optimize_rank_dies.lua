-- tests/cli: an optimization spec whose evaluations kill their own process on one MPI rank (the
-- rank named by GAITLAB_TEST_DYING_RANK; all of them when it is "all"), as a node lost would,
-- and that does not load on the rank named by GAITLAB_TEST_BROKEN_RANK
local dying = os.getenv("GAITLAB_TEST_DYING_RANK")
local rank = os.getenv("OMPI_COMM_WORLD_RANK") or os.getenv("PMIX_RANK")
if rank and os.getenv("GAITLAB_TEST_BROKEN_RANK") == rank then
  error("this rank cannot load the spec")
end

local function die()
  local stat = io.open("/proc/self/stat"):read("l")
  os.execute("kill -KILL " .. stat:match("^(%d+)"))
end

return {
  parameters = { amplitude = {10, 60, initial = 40}, phase = {30, 180, initial = 120} },
  build = function(p)
    if dying == "all" or dying == rank then die() end
    local robot = gaitlab.robot.chain{ name = "snake", modules = 3, connection = "pitch-pitch" }
    local world = gaitlab.world{}
    world:add(robot)
    robot:group("pitch"):drive(gaitlab.controllers.sine{ amplitude = p.amplitude,
                                                         phase = p.phase, frequency = 1 })
    return gaitlab.simulation{ world = world }
  end,
  fitness = "distance",
  duration = 0.5,
  method = "ga",
  population = 5,
  generations = 3,
}
