-- tests/cli: a module that is nowhere says where it was looked for
require "helpers.nowhere"
