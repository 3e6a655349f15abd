local n, i, c, s = 5000000, 1, 0, 0
while i <= n do
  s = (s * 31 + i) % 65521
  if s > 30000 then c = c + 1 end
  i = i + 1
end
print(c, s)
