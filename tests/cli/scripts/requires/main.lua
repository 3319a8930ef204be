-- tests/cli: require finds a module beside this script (a dotted name in folders), whatever the
-- working directory
local util = require "helpers.util"
print("util says " .. util.answer)
