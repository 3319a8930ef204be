-- Writes examples/terrain.png, the height map examples/terrain.lua loads: a 96 x 64 grey-level
-- PNG (white = highest) of a few smooth bumps and a furrow. Pure Lua: the image data goes into
-- uncompressed ("stored") deflate blocks, which every PNG reader accepts.
--
--   gaitlab run tools/make_terrain_png.lua [OUT.png]     (default examples/terrain.png)
local out = arg[1] or "examples/terrain.png"
local width, height = 96, 64

-- grey level of pixel (i, j), i from the left, j from the top, in [0, 255]
local function level(i, j)
  local x, y = i / (width - 1), 1 - j / (height - 1)  -- x to the right, y up, in [0, 1]
  local function bump(cx, cy, r) return math.exp(-((x - cx) ^ 2 + (y - cy) ^ 2) / r ^ 2) end
  local h = 0.9 * bump(0.55, 0.5, 0.12) + 0.6 * bump(0.8, 0.25, 0.1) + 0.5 * bump(0.75, 0.8, 0.15)
    + 0.25 * (1 + math.cos(2 * math.pi * x * 6)) * bump(0.3, 0.5, 0.3) * 0.6
  return math.floor(math.min(1, h) * 255 + 0.5)
end

local crc_table = {}
for n = 0, 255 do
  local c = n
  for _ = 1, 8 do c = (c & 1) == 1 and (0xEDB88320 ~ (c >> 1)) or (c >> 1) end
  crc_table[n] = c
end
local function crc32(s)
  local c = 0xFFFFFFFF
  for k = 1, #s do c = crc_table[(c ~ s:byte(k)) & 0xFF] ~ (c >> 8) end
  return c ~ 0xFFFFFFFF
end
local function adler32(s)
  local a, b = 1, 0
  for k = 1, #s do a = (a + s:byte(k)) % 65521; b = (b + a) % 65521 end
  return (b << 16) | a
end
local function chunk(kind, data)
  return string.pack(">I4", #data) .. kind .. data .. string.pack(">I4", crc32(kind .. data))
end

-- every row starts with filter type 0 (none)
local rows = {}
for j = 0, height - 1 do
  local row = { "\0" }
  for i = 0, width - 1 do row[#row + 1] = string.char(level(i, j)) end
  rows[#rows + 1] = table.concat(row)
end
local raw = table.concat(rows)

-- a zlib stream of stored blocks of at most 65535 bytes
local blocks = { "\x78\x01" }
for first = 1, #raw, 65535 do
  local part = raw:sub(first, first + 65534)
  local final = first + 65535 > #raw and 1 or 0
  blocks[#blocks + 1] = string.pack("<BI2I2", final, #part, (~#part) & 0xFFFF) .. part
end
blocks[#blocks + 1] = string.pack(">I4", adler32(raw))

local png = "\x89PNG\r\n\x1a\n"
  .. chunk("IHDR", string.pack(">I4I4BBBBB", width, height, 8, 0, 0, 0, 0))
  .. chunk("IDAT", table.concat(blocks))
  .. chunk("IEND", "")
local f = assert(io.open(out, "wb"))
f:write(png)
f:close()
print(string.format("%s: %d x %d grey levels", out, width, height))
