-- tests/cli: a module with a syntax error is named with its file and line
require "helpers.bad_syntax"
