local function fix3(v)
  if v >= 0 then return math.floor(v * 1000 + 0.5) / 1000 else return -math.floor(-v * 1000 + 0.5) / 1000 end
end
local n, t, m = 1, 0, 0
while n < 60000 do
  local x, r = n, 0
  while x ~= 1 do
    if x % 2 == 0 then x = x // 2 else x = 3 * x + 1 end
    r = r + 1
  end
  t = t + r
  m = fix3(m + (r - m) / 8)
  n = n + 1
end
print(t, string.format("%.3f", m))
