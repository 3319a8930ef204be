-- strict: names with slashes, dots, quotes, newlines, backticks and bytes that are not UTF-8, saved to files
local names = { "a/b", "../up", "..", "/abs", "q\"uote", "it's", "new\nline", "`tick`", "$(x)",
                "\xff\xfe", "", ("n"):rep(300), "<x/>", "&amp;" }
for _, name in ipairs(names) do
  local ok, robot = pcall(gaitlab.robot.chain, { name = name, modules = 2 })
  if ok then
    print(robot.name == name, robot:save("named.robot.xml"))
    local back = gaitlab.robot.load("named.robot.xml")
    print(back and back.name == name)
    local world = gaitlab.world{}
    world:add(robot)
    local sim = gaitlab.simulation{ world = world }
    print(sim:save("sim.xml"))
  end
  print(pcall(gaitlab.module, { name = name }))
  print(pcall(gaitlab.controller, { name = name, step = print }))
end
