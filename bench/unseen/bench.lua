-- The unseen benchmark of bench.mb in Lua 5.4.
local n = 10000000
local c, f = 0, 0.0
for i = 1, n do
  local m = i % 7
  f = f * 0.875 + m * 0.125
  if f > 3.5 then c = c + 1 end
end
print(string.format("C=%d F=%.6f", c, f))
