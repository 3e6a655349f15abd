local n, c, f, i = 10000000, 0, 0.0, 1
while i <= n do
  local m = i % 7
  f = f * 0.875 + m * 0.125
  if f > 3.5 then c = c + 1 end
  i = i + 1
end
print(c, f)
