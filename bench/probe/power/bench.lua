local y = 0
for i = 1, 1000000 do
  local x = i / 1000
  y = y + x ^ 2 - x ^ 0.5 + math.abs(x - 500) / (1 + x)
end
print(string.format("%.10g", y))
