local s, n = 0, 0
for x = 0, 2000, 0.001 do
  s = s + x * x - 3 * x
  if s > 1000000 then s = s - 1000000; n = n + 1 end
end
print(string.format("%.10g", s), n)
