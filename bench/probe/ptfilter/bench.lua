local c, f = 0, 0.0
for i = 1, 2000000 do
  local m = i % 7
  f = f * 0.875 + m * 0.125
  f = math.floor(f * 1000 + 0.5) / 1000
  if f > 3.5 then c = c + 1 end
end
print(c, f)
