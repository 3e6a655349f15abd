-- Branches and counters: the algorithm of mb/bench.mb and pt/bench.pt in Lua 5.4.
local p, a, b, c, d = 0, 0, 0, 0, 0
for i = 1, 8000000 do
  p = p + 7
  if p >= 100 then p = p - 100 end
  if p < 25 then
    a = a + 1
  else
    if p < 50 then
      b = b + 1
    else
      if p < 75 or p == 99 then
        c = c + 1
      else
        d = d + 2
      end
    end
  end
end
print(string.format("P=%d A=%d B=%d C=%d D=%d", p, a, b, c, d))
