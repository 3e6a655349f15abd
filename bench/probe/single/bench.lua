local c, s = 0, 0
for i = 1, 2000000 do
  local k = i % 13
  if k > 6 then c = c + 1 end
  s = s + k
end
print(c, s)
