local i, s, c = 0, 0, 0
repeat
  i = i + 1
  s = (s + i * 3) % 10007
  if s > 5000 then c = c + 1 end
until not (i < 3000000)
print(s, c)
