local a, b, s = 0, 1, 0
for i = 1, 3000000 do
  local c = (a + b) % 10007
  a = b; b = c
  s = (s + c) % 10007
end
print(s)
