-- Kernel calls: the algorithm of mb/bench.mb and pt/bench.pt in Lua 5.4; the kernel is a
-- table of axes and two functions reading it.
local axes = { { pos = 0.0, status = 0 } }
local function pos(n) return axes[n].pos end
local function statussv(n) return axes[n].status end
local s, g = 0.0, 0
for i = 1, 2000000 do
  s = s + pos(1) + 0.5
  if statussv(1) == 0 then g = g + 1 end
end
print(string.format("S=%.1f G=%d", s, g))
