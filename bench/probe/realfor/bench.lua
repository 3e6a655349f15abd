local y, s, c = 0, 0, 0
for i = 1, 2000000 do
  local x = (i % 100) / 10
  y = y + (x - y) * 0.05
  if y > 4.5 then c = c + 1 end
  s = s + y
end
print(c, string.format("%.7g", s))
