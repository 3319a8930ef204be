-- Runs every command of a Markdown tutorial (docs/tutorial.md), in order, in an empty folder,
-- the way a reader following it would:
--   * a ```lua block right after a line naming a file ("Save this as `turn.lua`:") is written
--     to that file (folders created);
--   * a ```sh block runs in bash with -e: every command must succeed;
--   * a ```console block starts with "$ COMMAND"; the lines that start with "> " or ">> " are
--     what the reader types, fed to COMMAND on standard input; the other lines are sample
--     output. The session must end with status 0 and, unless the sample output shows one, print
--     no Lua traceback.
-- `gaitlab` in commands is the binary under test.
--
-- usage: lua5.4 run_tutorial.lua TUTORIAL.md GAITLAB_BINARY WORK_FOLDER
local doc_path, binary, work = arg[1], arg[2], arg[3]
assert(doc_path and binary and work, "usage: lua5.4 run_tutorial.lua TUTORIAL.md GAITLAB WORK")

local function quote(s) return "'" .. s:gsub("'", "'\\''") .. "'" end

local function run(cmd)
  local ok, how, code = os.execute(cmd)
  return ok and 0 or (how == "signal" and 128 + code or code)
end

local function read(path)
  local f = assert(io.open(path, "rb"))
  local s = f:read("a")
  f:close()
  return s
end

local function write(path, text)
  local dir = path:match("^(.*)/[^/]*$")
  if dir then assert(run("mkdir -p " .. quote(work .. "/" .. dir)) == 0) end
  local f = assert(io.open(work .. "/" .. path, "wb"))
  f:write(text)
  f:close()
end

-- a folder whose only `gaitlab` is the binary under test, first on PATH
assert(run("rm -rf " .. quote(work) .. " && mkdir -p " .. quote(work .. "/.bin")) == 0)
assert(run("ln -s " .. quote(binary) .. " " .. quote(work .. "/.bin/gaitlab")) == 0)
local env = "cd " .. quote(work) .. " && PATH=" .. quote(work .. "/.bin") .. ":\"$PATH\" " ..
            "XDG_STATE_HOME=" .. quote(work .. "/.state") .. " EDITOR= VISUAL= "

local failures, blocks = 0, 0
local function fail(line, what, output)
  failures = failures + 1
  io.stderr:write(("%s:%d: %s\n%s\n"):format(doc_path, line, what, output or ""))
end

local lines = {}
for l in (read(doc_path) .. "\n"):gmatch("(.-)\n") do lines[#lines + 1] = l end

local i, previous = 1, ""
while i <= #lines do
  local kind = lines[i]:match("^```(%S*)%s*$")
  if kind and kind ~= "" then
    local start, body = i, {}
    i = i + 1
    while i <= #lines and not lines[i]:match("^```%s*$") do
      body[#body + 1] = lines[i]
      i = i + 1
    end
    local text = table.concat(body, "\n") .. "\n"
    local out = work .. "/.out"
    if kind == "lua" then
      local file = previous:match("`([%w_%-%./]+%.lua)`[^`]*:%s*$")
      if file then
        write(file, text)
        blocks = blocks + 1
      end
    elseif kind == "sh" then
      blocks = blocks + 1
      write(".block.sh", text)
      if run(env .. "bash -eo pipefail .block.sh >" .. quote(out) .. " 2>&1") ~= 0 then
        fail(start, "a command of this block failed", read(out))
      end
    elseif kind == "console" then
      blocks = blocks + 1
      local command = assert(body[1]:match("^%$ (.+)$"), doc_path .. ":" .. start ..
                             ": a console block starts with '$ COMMAND'")
      local typed, shown = {}, {}
      for k = 2, #body do
        local input = body[k]:match("^>>? (.*)$") or (body[k] == ">" and "")
        if input then typed[#typed + 1] = input else shown[#shown + 1] = body[k] end
      end
      write(".typed", table.concat(typed, "\n") .. "\n")
      local status = run(env .. command .. " < .typed >" .. quote(out) .. " 2>&1")
      local output = read(out)
      if status ~= 0 then
        fail(start, ("'%s' ended with status %d"):format(command, status), output)
      elseif output:find("stack traceback:", 1, true) and
             not table.concat(shown, "\n"):find("stack traceback:", 1, true) then
        fail(start, "a typed line failed", output)
      end
    end
  elseif lines[i]:match("%S") then
    previous = lines[i]
  end
  i = i + 1
end

if blocks == 0 then fail(1, "no block to run") end
if failures > 0 then
  io.stderr:write(("%d of %d blocks failed\n"):format(failures, blocks))
  os.exit(1)
end
print(("%s: all %d blocks ran"):format(doc_path, blocks))
