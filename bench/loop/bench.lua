-- Counting-loop benchmark: the loop of bench.pt in Lua 5.4.
local s, t = 0, 0
for i = 1, 20000000 do
  s = s + 3
  if s > 1000000 then
    s = s - 1000000
    t = t + 1
  end
end
print(string.format("S=%d T=%d", s, t))
