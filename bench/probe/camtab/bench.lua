local t = {}
local p = 3.14159265358979
local m, s = 0.0, 0.0
for r = 1, 200 do
  for i = 0, 359 do
    t[i] = 1000 * (1 - math.cos(i * p / 180)) / 2
  end
  for i = 0, 359 do
    s = s + t[i]
    if t[i] > m then m = t[i] end
  end
end
print(string.format("%.15g", s), string.format("%.7g", m))
