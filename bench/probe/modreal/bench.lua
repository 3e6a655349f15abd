local s, t = 0, 0
for i = 1, 10000000 do
  s = s + (i & 7)
  s = s ~ i
  t = t + (i % 2) / 4
end
print(s, string.format("%.7g", t))
